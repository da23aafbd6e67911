// `trisnap assess` through the binary: exit codes and messages, the JSON file, --fail-on-defects,
// and trisnap's own output on real layers (defect counts 0, separations held).
#include "assess_fixture.hpp"
#include "cli_support.hpp"

#include <gtest/gtest.h>

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
        EXPECT_EQ(r.code, code) << r.err;
        ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    };
    expect({in, in, "--tolerance", "0"}, 2, "--tolerance");
    expect({in, in, "--tolerance", "-1"}, 2, "--tolerance");
    expect({in, in}, 2, "tolerance");
    expect({in, in, "--tolerance", "1", "--layer-b", "nope"}, 2, "nope");
    expect({in, in, "--tolerance", "1", "--key", "nope"}, 2, "nope");
    expect({in, dir.path("absent.gpkg"), "--tolerance", "1"}, 1, "absent.gpkg");
    expect({in, in, "--tolerance", "1", "--json", dir.path("no/such/dir/r.json")}, 1, "r.json");
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

} // namespace
} // namespace trisnap::test
