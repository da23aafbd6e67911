// `trisnap assess` through the binary: exit codes and messages, the JSON file, --fail-on-defects,
// and trisnap's own output on real layers (defect counts 0, separations held); an .osm.pbf read
// as snap reads it; the bundled sample judged with its snap report; corrupt and empty inputs.
#include "assess_fixture.hpp"
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace trisnap::test {
namespace {

void write_gpkg(const std::string& path, const std::vector<Item>& items)
{
    GDALDatasetUniquePtr ds = make_layer(items, wkbUnknown, "GPKG", path);
    ASSERT_TRUE(ds);
}

/// The features of `layer` in `src` whose boxes meet `bbox`, with their FIDs, into a GeoPackage.
void copy_window(const std::string& src, const std::string& layer_name, const std::vector<double>& bbox,
                 const std::string& dst)
{
    GDALAllRegister();
    GDALDatasetUniquePtr in(GDALDataset::Open(src.c_str(), GDAL_OF_VECTOR));
    ASSERT_TRUE(in);
    OGRLayer* layer = in->GetLayerByName(layer_name.c_str());
    ASSERT_NE(layer, nullptr);
    layer->SetSpatialFilterRect(bbox[0], bbox[1], bbox[2], bbox[3]);
    GDALDatasetUniquePtr out(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(dst.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRLayer* copy = out->CopyLayer(layer, layer_name.c_str(), nullptr);
    ASSERT_NE(copy, nullptr);
}

const std::vector<Item> k_in{{1, square(0, 0, 1), "a"}, {2, square(1, 0, 1), "b"}};

TEST(AssessCli, TableJsonAndExitCodes)
{
    TempDir dir;
    write_gpkg(dir.path("in.gpkg"), k_in);
    write_gpkg(dir.path("bad.gpkg"), {{1, "POLYGON((0 0,1 1,1 0,0 1,0 0))", "a"}, {2, square(1, 0, 1), "b"}});
    RunOutput r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("in.gpkg"), "--tolerance", "0.1",
                                    "--json", dir.path("r.json"), "--fail-on-defects"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("contract              holds"), std::string::npos) << r.out;
    nlohmann::json j = read_json(dir.path("r.json"));
    EXPECT_EQ(j["n_in"], 2);
    EXPECT_EQ(j["contract_holds"], true);
    EXPECT_EQ(j["min_vertex_vertex_over_t"], 10.0);

    r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("bad.gpkg"), "--tolerance", "0.1", "--json",
                          dir.path("bad.json"), "--fail-on-defects"});
    EXPECT_EQ(r.code, 3) << r.err;
    j = read_json(dir.path("bad.json"));
    EXPECT_EQ(j["n_invalid"], 1);
    EXPECT_EQ(j["examples"]["invalid"][0]["fid"], 1);
    EXPECT_EQ(j["contract_holds"], false);
    r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("bad.gpkg"), "--tolerance", "0.1"});
    EXPECT_EQ(r.code, 0) << "without --fail-on-defects, defects are data";
}

TEST(AssessCli, RenumberedOutputsMatchThroughOrigFid)
{
    TempDir dir;
    write_gpkg(dir.path("in.gpkg"), {{5, square(0, 0, 1), "a"}, {9, square(1, 0, 1), "b"}});
    RunOutput r = run_trisnap(dir, {"snap", dir.path("in.gpkg"), dir.path("out.fgb"), "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("out.fgb"), "--tolerance", "0.01", "--json",
                          dir.path("r.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(dir.path("r.json"));
    EXPECT_EQ(j["matched_by"], "orig_fid");
    EXPECT_EQ(j["n_matched"], 2);
    EXPECT_EQ(j["n_missing"], 0);
    EXPECT_EQ(j["n_extra"], 0);
    EXPECT_EQ(j["n_attr_mismatch"], 0);
}

TEST(AssessCli, ErrorsAreOneLineWithTheRightCode)
{
    TempDir dir;
    write_gpkg(dir.path("in.gpkg"), k_in);
    const std::string in = dir.path("in.gpkg");
    const auto expect = [&](std::vector<std::string> args, int code, const std::string& needle) {
        args.insert(args.begin(), "assess");
        const RunOutput r = run_trisnap(dir, args);
        EXPECT_EQ(r.code, code) << needle << ": " << r.err;
        ASSERT_EQ(r.err_lines().size(), 1u) << needle << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    };
    expect({in, in, "--tolerance", "0"}, 2, "--tolerance");
    expect({in, in, "--tolerance", "-1"}, 2, "--tolerance");
    expect({in, in}, 2, "no tolerance");
    expect({in, in, "--tolerance", "1", "--tolerance-m", "1"}, 2, "not both");
    expect({in, in, "--tolerance-m", "nan"}, 2, "--tolerance-m must be finite and > 0");
    expect({in, in, "--tolerance", "1", "--report", dir.path("none.json")}, 1, "none.json");
    expect({in, in, "--tolerance", "1", "--layer-b", "nope"}, 2, "nope");
    expect({in, in, "--tolerance", "1", "--key", "nope"}, 2, "nope");
    expect({in, dir.path("absent.gpkg"), "--tolerance", "1"}, 1, "absent.gpkg");
    // A --json path that cannot name a file is refused before measuring, as snap's --report is.
    expect({in, in, "--tolerance", "1", "--json", dir.path("no/such/dir/r.json")}, 2, "r.json");
    expect({in, in, "--tolerance", "1", "--json", in}, 2, "is a file of ORIGINAL");
}

TEST(AssessCli, TrisnapOutputOnACoverageHasNoDefects)
{
    const std::string src = data_dir() + "/bgt_delft_3dfier/bgt_delft.gpkg";
    if (!exists(src)) GTEST_SKIP() << src << " is absent";
    TempDir dir;
    copy_window(src, "bgt_maaiveld_partition", {84700, 447450, 84950, 447700}, dir.path("in.gpkg"));
    RunOutput r = run_trisnap(dir, {"snap", dir.path("in.gpkg"), dir.path("out.gpkg"), "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("out.gpkg"), "--tolerance", "0.01", "--json",
                          dir.path("r.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(dir.path("r.json"));
    EXPECT_GT(j["n_in"].get<int>(), 200);
    EXPECT_GT(j["n_shared_in"].get<int>(), 200);
    for (const char* key : {"n_missing", "n_extra", "n_attr_mismatch", "n_invalid", "n_empty", "n_overlaps",
                            "gaps_new", "n_crossings"})
        EXPECT_EQ(j[key], 0) << key;
    EXPECT_GE(j["min_vertex_vertex"].get<double>(), 0.01);
    EXPECT_GE(j["min_vertex_edge"].get<double>(), 0.005);
}

TEST(AssessCli, TrisnapOutputOnAndorraKeepsSeparations)
{
    const std::string src = data_dir() + "/snapoly_andorra/andorra.gpkg";
    if (!exists(src)) GTEST_SKIP() << src << " is absent";
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"snap", src, dir.path("out.gpkg"), "--tolerance", "1e-6", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"assess", src, dir.path("out.gpkg"), "--tolerance", "1e-6", "--json", dir.path("r.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(dir.path("r.json"));
    // The input itself overlaps (OSM landuse) and crosses; the snapped output must not cross.
    r = run_trisnap(dir, {"assess", src, src, "--tolerance", "1e-6", "--json", dir.path("in.json")});
    const nlohmann::json input = read_json(dir.path("in.json"));
    EXPECT_GT(input["n_crossings"].get<int>(), 0);
    for (const char* key : {"n_missing", "n_extra", "n_attr_mismatch", "n_invalid", "n_empty", "gaps_new", "n_crossings"})
        EXPECT_EQ(j[key], 0) << key;
    EXPECT_LE(j["n_overlaps"].get<int>(), input["n_overlaps"].get<int>());
    EXPECT_EQ(j["n_overlaps_new"], 0);
    EXPECT_GE(j["min_vertex_vertex"].get<double>(), 1e-6);
    EXPECT_GE(j["min_vertex_edge"].get<double>(), 0.5e-6);
}

/// Every coordinate of every feature rounded to `grid`, feature by feature, as GEOS's
/// setPrecision without topology would: overlaps, crossings and collapses between neighbours.
void round_to_grid(OGRGeometry& g, double grid)
{
    if (auto* curve = dynamic_cast<OGRSimpleCurve*>(&g)) {
        for (int i = 0; i < curve->getNumPoints(); ++i) {
            curve->setPoint(i, std::round(curve->getX(i) / grid) * grid, std::round(curve->getY(i) / grid) * grid);
        }
    } else if (auto* polygon = dynamic_cast<OGRPolygon*>(&g)) {
        for (OGRLinearRing* ring : *polygon) {
            round_to_grid(*ring, grid);
        }
    } else if (auto* collection = dynamic_cast<OGRGeometryCollection*>(&g)) {
        for (OGRGeometry* member : *collection) {
            round_to_grid(*member, grid);
        }
    }
}

void write_rounded_copy(const std::string& src, const std::string& dst, double grid)
{
    GDALAllRegister();
    std::filesystem::copy_file(src, dst);
    GDALDatasetUniquePtr out(GDALDataset::Open(dst.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
    ASSERT_TRUE(out);
    OGRLayer* layer = out->GetLayer(0);
    std::vector<OGRFeatureUniquePtr> features;
    for (auto& f : *layer) {
        features.emplace_back(f->Clone());
    }
    for (OGRFeatureUniquePtr& f : features) {
        if (OGRGeometry* g = f->GetGeometryRef()) {
            round_to_grid(*g, grid);
            ASSERT_EQ(layer->SetFeature(f.get()), OGRERR_NONE);
        }
    }
}

TEST(AssessCli, OsmPbfIsReadAsSnapReadsItAndGatesCi)
{
    const std::string src = data_dir() + "/osm_small_extracts/andorra_graphhopper_2013.osm.pbf";
    if (!exists(src)) {
        GTEST_SKIP() << src << " is absent";
    }
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"snap", src, dir.path("out.gpkg"), "--layer", "multipolygons", "--tolerance-m", "0.05",
                                    "--report", dir.path("snap.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json snap = read_json(dir.path("snap.json"));
    r = run_trisnap(dir, {"assess", src, dir.path("out.gpkg"), "--layer-a", "multipolygons", "--tolerance-m", "0.05",
                          "--report", dir.path("snap.json"), "--json", dir.path("ok.json"), "--fail-on-defects"});
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json ok = read_json(dir.path("ok.json"));
    EXPECT_EQ(ok["n_in"], snap["counts"]["input"]) << "every feature read, interleaved, as snap read them";
    EXPECT_GT(ok["n_in"].get<int>(), 600);
    EXPECT_EQ(ok["n_matched"], ok["n_in"]);
    EXPECT_EQ(ok["tolerance"], snap["config"]["tolerance_layer_units"]) << "--tolerance-m converted as snap converts it";
    EXPECT_GT(ok["n_overlaps"].get<int>(), 0) << "OSM landuse overlaps already";
    EXPECT_EQ(ok["n_overlaps_new"], 0);
    EXPECT_EQ(ok["contract_holds"], true);

    write_rounded_copy(dir.path("out.gpkg"), dir.path("geos_like.gpkg"), 1e-5);
    r = run_trisnap(dir, {"assess", src, dir.path("geos_like.gpkg"), "--layer-a", "multipolygons", "--tolerance-m", "0.05",
                          "--json", dir.path("bad.json"), "--fail-on-defects"});
    EXPECT_EQ(r.code, 3) << r.out << r.err;
    const nlohmann::json bad = read_json(dir.path("bad.json"));
    EXPECT_GT(bad["n_overlaps_new"].get<int>() + bad["n_crossings_new"].get<int>() + bad["n_invalid"].get<int>(), 0);
}

TEST(AssessCli, BundledSampleHoldsWithTheExcusesOfItsSnapReport)
{
    const std::string src = std::string(TRISNAP_SOURCE_DIR) + "/data/delft_partition_sample.gpkg";
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"snap", src, dir.path("out.gpkg"), "--tolerance", "0.05", "--report",
                                    dir.path("snap.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json snap = read_json(dir.path("snap.json"));
    ASSERT_GT(snap["problems"].size(), 0u) << "the sample has thin parts that collapse at 5 cm";
    r = run_trisnap(dir, {"assess", src, dir.path("out.gpkg"), "--tolerance", "0.05", "--fail-on-defects"});
    EXPECT_EQ(r.code, 3) << "without the report, the drift of the collapsed thin parts fails the contract";
    EXPECT_NE(r.out.find("features drift > 2T"), std::string::npos) << r.out;
    r = run_trisnap(dir, {"assess", src, dir.path("out.gpkg"), "--report", dir.path("snap.json"), "--json",
                          dir.path("a.json"), "--fail-on-defects"});
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("contract              holds"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("explained by the snap report"), std::string::npos) << r.out;
    const nlohmann::json j = read_json(dir.path("a.json"));
    EXPECT_EQ(j["tolerance"], 0.05) << "taken from the report";
    EXPECT_GT(j["excused"]["total"].get<int>(), 0);
    EXPECT_EQ(j["excused"]["drift"], j["n_drift"]);
    for (const auto& e : j["examples"]["excused"]) {
        bool reported = false;
        for (const auto& p : snap["problems"]) {
            reported = reported || (p["fid"] == e["fid_a"] && e["excused_by"].get<std::string>().find(std::to_string(p["code"].get<int>())) != std::string::npos);
        }
        EXPECT_TRUE(reported) << e.dump() << ": excused by a code the report gives that feature";
    }
}

TEST(AssessCli, NoFeatureReadIsAnError)
{
    TempDir dir;
    write_gpkg(dir.path("in.gpkg"), k_in);
    write_gpkg(dir.path("empty.gpkg"), {});
    const RunOutput r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("empty.gpkg"), "--tolerance", "0.1"});
    EXPECT_EQ(r.code, 1);
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("empty.gpkg (layer 'l'): no features read"), std::string::npos) << r.err;
}

TEST(AssessCli, ACorruptGeometryIsAnErrorNotData)
{
    TempDir dir;
    write_gpkg(dir.path("in.gpkg"), k_in);
    write_gpkg(dir.path("bad.gpkg"), k_in);
    {
        GDALDatasetUniquePtr ds(GDALDataset::Open(dir.path("bad.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
        ASSERT_TRUE(ds);
        const std::string column = ds->GetLayer(0)->GetGeometryColumn();
        ds->ExecuteSQL(("UPDATE l SET \"" + column + "\" = X'4750000100000000DEADBEEF' WHERE fid = 2").c_str(), nullptr, nullptr);
    }
    const RunOutput r = run_trisnap(dir, {"assess", dir.path("in.gpkg"), dir.path("bad.gpkg"), "--tolerance", "0.1"});
    EXPECT_EQ(r.code, 1) << r.out;
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("bad.gpkg (layer 'l'): feature FID 2: "), std::string::npos) << r.err;
}

} // namespace
} // namespace trisnap::test
