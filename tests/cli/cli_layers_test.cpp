// Several layers in one run (`snap --layer A --layer B`): one triangulation for both, each
// written to its own output layer. A fixture of two polygon layers whose edges lie within t/3 of
// each other without coinciding (FIDs 1..n in both) must come out with the near vertices shared
// bit for bit (a run per layer does not do that), vertices >= t apart across layers, a problem of
// layer B reported as B's, and the same bytes whatever the threads, tiles, or memory; the errors
// (a layer twice, another CRS, -nln, a one-layer format, a resume with other layers) stop before
// anything is written. One real two-layer run (BGT Delft buildings and roads) is checked with the
// independent contract checker on both layers together.
#include "cli_support.hpp"
#include "problem_codes.hpp"
#include "contract_checker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>

namespace trisnap::test {
namespace {

namespace fs = std::filesystem;

constexpr double k_t = 0.01;

struct Poly {
    std::string wkt;
    std::string name;
};

/// Layer `name` with a String field "name", FIDs 1..n in order.
void add_layer(GDALDataset& ds, const std::string& name, int epsg, const std::vector<Poly>& polys)
{
    OGRSpatialReference srs;
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    srs.importFromEPSG(epsg);
    OGRLayer* layer = ds.CreateLayer(name.c_str(), &srs, wkbPolygon, nullptr);
    ASSERT_NE(layer, nullptr);
    OGRFieldDefn field("name", OFTString);
    ASSERT_EQ(layer->CreateField(&field), OGRERR_NONE);
    for (const Poly& p : polys) {
        OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        f->SetField("name", p.name.c_str());
        OGRGeometry* g = nullptr;
        ASSERT_EQ(OGRGeometryFactory::createFromWkt(p.wkt.c_str(), nullptr, &g), OGRERR_NONE) << p.wkt;
        f->SetGeometryDirectly(g);
        ASSERT_EQ(layer->CreateFeature(f.get()), OGRERR_NONE);
    }
}

/// A: three 10 x 10 squares 10 apart. B: two parcels filling the gaps between them, each corner
/// 0.002-0.003 (under t/3) off A's corners and each side 0.003 off A's sides; a third, tiny one
/// collapses (problem 201 of B's FID 3). C: as A, in another CRS.
std::string write_layers(const TempDir& dir)
{
    const std::string path = dir.path("in.gpkg");
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    EXPECT_TRUE(ds);
    const std::vector<Poly> a = {{"POLYGON ((0 0,10 0,10 10,0 10,0 0))", "a1"},
                                 {"POLYGON ((20 0,30 0,30 10,20 10,20 0))", "a2"},
                                 {"POLYGON ((40 0,50 0,50 10,40 10,40 0))", "a3"}};
    const std::vector<Poly> b = {{"POLYGON ((10.003 -0.002,19.997 -0.002,19.997 10.002,10.003 10.002,10.003 -0.002))", "b1"},
                                 {"POLYGON ((30.003 0.002,39.997 0.002,39.997 9.998,30.003 9.998,30.003 0.002))", "b2"},
                                 {"POLYGON ((100 100,100.004 100,100.004 100.004,100 100.004,100 100))", "b3"}};
    add_layer(*ds, "A", 3857, a);
    add_layer(*ds, "B", 3857, b);
    add_layer(*ds, "C", 4326, {{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", "c1"}});
    return path;
}

using Point = std::pair<double, double>;

/// Every vertex of every feature of `layer` in `path`.
std::vector<Point> vertices(const std::string& path, const std::string& layer)
{
    std::vector<Point> out;
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    EXPECT_TRUE(ds) << path;
    OGRLayer* l = ds ? ds->GetLayerByName(layer.c_str()) : nullptr;
    EXPECT_NE(l, nullptr) << layer;
    while (l != nullptr) {
        OGRFeatureUniquePtr f(l->GetNextFeature());
        if (!f) {
            break;
        }
        const OGRGeometry* g = f->GetGeometryRef();
        if (g == nullptr) {
            continue;
        }
        std::unique_ptr<OGRGeometry> lines(OGRGeometryFactory::forceToMultiLineString(g->clone()));
        for (const OGRGeometry* part : *lines->toMultiLineString()) {
            for (const OGRPoint& p : *part->toLineString()) {
                out.emplace_back(p.getX(), p.getY());
            }
        }
    }
    return out;
}

struct Pairs {
    std::size_t identical = 0; ///< an A vertex and a B vertex at exactly the same place
    std::size_t near = 0;      ///< an A vertex and a B vertex closer than t but not identical
};

Pairs across(const std::vector<Point>& a, const std::vector<Point>& b)
{
    Pairs p;
    std::set<Point> seen; // closing points repeat the first: count each place once
    for (const Point& u : a) {
        for (const Point& v : b) {
            if (u == v && seen.insert(u).second) {
                ++p.identical;
            } else if (u != v && std::hypot(u.first - v.first, u.second - v.second) < k_t) {
                ++p.near;
            }
        }
    }
    return p;
}

std::vector<std::string> snap(const std::string& in, const std::string& out, std::vector<std::string> extra = {})
{
    std::vector<std::string> args{"snap", in, out, "--layer", "A", "--layer", "B", "--tolerance", "0.01", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

TEST(CliLayers, TwoLayersSnapTogetherEachToItsOwnLayer)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, snap(in, out, {"--report", report, "--problems-layer", dir.path("p.gpkg")}));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const auto a = read_layer(out, "A");
    const auto b = read_layer(out, "B");
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 2u); // B's FID 3 collapsed
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].fid, static_cast<std::int64_t>(i + 1));
        EXPECT_EQ(a[i].fields.at("name"), std::string("a").append(std::to_string(i + 1)));
        EXPECT_TRUE(a[i].valid) << a[i].wkt;
    }
    for (std::size_t i = 0; i < b.size(); ++i) {
        EXPECT_EQ(b[i].fid, static_cast<std::int64_t>(i + 1));
        EXPECT_EQ(b[i].fields.at("name"), std::string("b").append(std::to_string(i + 1)));
        EXPECT_TRUE(b[i].valid) << b[i].wkt;
    }
    // Each of B1's and B2's 4 corners is now exactly an A corner; none is left merely near one.
    const Pairs together = across(vertices(out, "A"), vertices(out, "B"));
    EXPECT_EQ(together.identical, 8u);
    EXPECT_EQ(together.near, 0u);
    // Distinct vertices are >= t apart, across the layers too.
    std::vector<Point> all = vertices(out, "A");
    const std::vector<Point> vb = vertices(out, "B");
    all.insert(all.end(), vb.begin(), vb.end());
    for (const Point& u : all) {
        for (const Point& v : all) {
            if (u != v) {
                ASSERT_GE(std::hypot(u.first - v.first, u.second - v.second), k_t);
            }
        }
    }
    // The report: B's problem as B's, accounting per layer and in total.
    const nlohmann::json j = read_json(report);
    bool found = false;
    for (const auto& p : j["problems"]) {
        EXPECT_TRUE(p.contains("layer")) << p.dump();
        found = found || (p["fid"] == 3 && p["layer"] == "B" && p["code"] == 201);
    }
    EXPECT_TRUE(found) << j["problems"].dump();
    ASSERT_EQ(j["layers"].size(), 2u);
    for (const auto& l : j["layers"]) {
        const auto& c = l["counts"];
        EXPECT_EQ(c["input"], c["written"].get<int>() + c["rejected"].get<int>() + c["dropped"].get<int>() + c["unwritable"].get<int>()) << l.dump();
        EXPECT_EQ(l["fids"], "kept");
    }
    EXPECT_EQ(j["layers"][1]["counts"]["dropped"], 1);
    EXPECT_EQ(j["counts"]["input"], 6);
    EXPECT_EQ(j["counts"]["written"], 5);
    EXPECT_EQ(j["input"]["layer"], nlohmann::json::array({"A", "B"}));
    const auto problems = read_layer(dir.path("p.gpkg"), "problems");
    ASSERT_FALSE(problems.empty());
    EXPECT_EQ(problems.front().fields.at("layer"), "B");
}

TEST(CliLayers, EachLayerAloneDoesNotShareTheBoundary)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    for (const std::string layer : {"A", "B"}) {
        const RunOutput r = run_trisnap(dir, {"snap", in, dir.path(layer + ".gpkg"), "--layer", layer, "--tolerance", "0.01", "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const Pairs apart = across(vertices(dir.path("A.gpkg"), "A"), vertices(dir.path("B.gpkg"), "B"));
    EXPECT_EQ(apart.identical, 0u);
    EXPECT_GE(apart.near, 8u) << "snapped alone, B's corners stay within t of A's";
}

TEST(CliLayers, SameBytesWhateverThreadsTilesAndMemory)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    const std::string reference = dir.path("ref.gpkg");
    ASSERT_EQ(run_trisnap(dir, snap(in, reference, {"--threads", "1"})).code, 0);
    const std::string bytes = file_bytes(reference);
    const std::vector<std::vector<std::string>> variants = {
        {"--threads", "2"}, {"--no-tiles"}, {"--tile-size", "15", "--threads", "2"},
        {"--memory-limit", "256MiB"}, {"--memory-limit", "256MiB", "--tile-size", "15"}};
    for (std::size_t i = 0; i < variants.size(); ++i) {
        const std::string out = dir.path(std::string("v").append(std::to_string(i)).append(".gpkg"));
        const RunOutput r = run_trisnap(dir, snap(in, out, variants[i]));
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_TRUE(file_bytes(out) == bytes) << "bytes differ with " << variants[i].front();
    }
    // The layers the other way round: each output layer is the same as a layer.
    const std::string swapped = dir.path("swapped.gpkg");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, swapped, "--layer", "B", "--layer", "A", "--tolerance", "0.01", "-q"}).code, 0);
    for (const std::string layer : {"A", "B"}) {
        const auto x = read_layer(reference, layer);
        const auto y = read_layer(swapped, layer);
        ASSERT_EQ(x.size(), y.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            EXPECT_EQ(x[i].wkt, y[i].wkt) << layer << " " << x[i].fid;
        }
    }
}

TEST(CliLayers, ErrorsNameWhatIsWrongAndLeaveNoOutput)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    const std::string out = dir.path("out.gpkg");
    const std::vector<std::string> t{"--tolerance", "0.01"};
    struct Case {
        std::vector<std::string> args;
        std::string text;
    };
    const std::vector<Case> cases = {
        {{in, out, "--layer", "A", "--layer", "A"}, "--layer A is given twice"},
        {{in, out, "--layer", "A", "--layer", "C"}, "--layer A and --layer C have different CRSs (A: EPSG:3857"},
        {{in, out, "--layer", "A", "--layer", "Z"}, "no layer 'Z'; layers: A (Polygon), B (Polygon), C (Polygon)"},
        {{in, out, "--layer", "A", "--layer", "B", "-nln", "X"}, "-nln X: it names one output layer, and 2 layers were given"},
        {{in, dir.path("out.shp"), "--layer", "A", "--layer", "B"},
         "the ESRI Shapefile format holds one layer per file, and layers 'A', 'B' go to one OUT; write them to a format "
         "that holds several, e.g. out.gpkg"},
        {{in, dir.path("out.geojson"), "--layer", "A", "--layer", "B"}, "the GeoJSON format holds one layer per file"},
    };
    for (const std::string command : {"snap", "validate"}) {
        for (const Case& c : cases) {
            std::vector<std::string> args{command};
            args.insert(args.end(), c.args.begin(), c.args.end());
            args.insert(args.end(), t.begin(), t.end());
            expect_error(run_trisnap(dir, args), 2, c.text);
            EXPECT_FALSE(fs::exists(c.args[1])) << c.args[1];
        }
    }
    expect_error(run_trisnap(dir, {"plan", in, dir.path("run"), "--layer", "A", "--layer", "B", "--tolerance", "0.01"}), 2,
                 "trisnap plan takes one --layer");
}

TEST(CliLayers, UpdateOverwriteAndAppendActPerOutputLayer)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    const std::string out = dir.path("out.gpkg");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, out, "--layer", "C", "--tolerance", "1e-7", "-q"}).code, 0);
    ASSERT_EQ(run_trisnap(dir, {"snap", in, out, "--layer", "A", "--tolerance", "0.01", "-q", "--update"}).code, 0);
    const std::string before = file_bytes(out);
    expect_error(run_trisnap(dir, snap(in, out, {"--update"})), 2,
                 "has a layer 'A' already; add --overwrite to replace it or --append to add to it");
    EXPECT_TRUE(file_bytes(out) == before) << "a refused --update changed OUT";
    ASSERT_EQ(run_trisnap(dir, snap(in, out, {"--overwrite"})).code, 0);
    EXPECT_EQ(read_layer(out, "C").size(), 1u) << "--overwrite replaced a layer it does not write";
    EXPECT_EQ(read_layer(out, "A").size(), 3u);
    EXPECT_EQ(read_layer(out, "B").size(), 2u);
    ASSERT_EQ(run_trisnap(dir, snap(in, out, {"--append"})).code, 0);
    EXPECT_EQ(read_layer(out, "A").size(), 6u);
    EXPECT_EQ(read_layer(out, "B").size(), 4u);
    EXPECT_EQ(read_layer(out, "C").size(), 1u);
}

TEST(CliLayers, ResumeOnlyWithTheSameLayers)
{
    TempDir dir;
    const std::string in = write_layers(dir);
    const std::string out = dir.path("out.gpkg");
    const std::string work = dir.path("work");
    RunOutput r = run_trisnap(dir, snap(in, out, {"--work-dir", work, "--memory-limit", "1MiB"}));
    ASSERT_EQ(r.code, 2) << r.err;
    ASSERT_TRUE(fs::exists(work + "/manifest.json")) << "no work directory kept";
    r = run_trisnap(dir, {"snap", in, out, "--layer", "A", "--tolerance", "0.01", "--work-dir", work,
                          "--memory-limit", "256MiB", "--resume"});
    expect_error(r, 2, "differs in input.layer");
    r = run_trisnap(dir, snap(in, out, {"--work-dir", work, "--memory-limit", "256MiB", "--resume"}));
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(run_trisnap(dir, snap(in, dir.path("ref.gpkg"))).code, 0);
    EXPECT_TRUE(file_bytes(out) == file_bytes(dir.path("ref.gpkg"))) << "resumed bytes differ";
}

// Real data: BGT Delft buildings (bgt_pand) and roads (bgt_wegdeel), EPSG:28992, at 1 cm.
TEST(CliLayers, RealLayersKeepTheContractTogether)
{
    const std::string in = data_dir() + "/bgt_delft_3dfier/bgt_delft.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    TempDir dir;
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    const std::vector<std::string> layers{"bgt_pand", "bgt_wegdeel"};
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--layer", layers[0], "--layer", layers[1], "--tolerance", "0.01",
                                          "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(report);
    std::vector<CheckedFeature> input;
    std::vector<CheckedFeature> output;
    std::size_t total = 0;
    for (std::size_t k = 0; k < layers.size(); ++k) {
        const auto before = read_layer(in, layers[k]);
        const auto after = read_layer(out, layers[k]);
        const auto& c = j["layers"][k]["counts"];
        EXPECT_EQ(c["input"].get<std::size_t>(), before.size());
        EXPECT_EQ(c["written"].get<std::size_t>(), after.size());
        EXPECT_EQ(c["input"], c["written"].get<int>() + c["rejected"].get<int>() + c["dropped"].get<int>() + c["unwritable"].get<int>());
        total += before.size();
        const std::int64_t base = static_cast<std::int64_t>(k) << 32; // FIDs repeat across layers
        for (const ReadFeature& f : before) {
            input.push_back({base + f.fid, f.wkt});
        }
        for (const ReadFeature& f : after) {
            output.push_back({base + f.fid, f.wkt});
        }
    }
    EXPECT_EQ(j["counts"]["input"].get<std::size_t>(), total);
    std::vector<ReportedProblem> problems;
    std::set<std::int64_t> flagged;
    const std::vector<int> drift{105, 201, 202, 203, 204, 206, 208, 209};
    for (const auto& p : j["problems"]) {
        const std::int64_t k = p["layer"] == layers[0] ? 0 : 1;
        problems.push_back({(k << 32) + p["fid"].get<std::int64_t>(), p["code"].get<int>()});
        if (std::find(drift.begin(), drift.end(), problems.back().code) != drift.end()) {
            flagged.insert(problems.back().id);
        }
    }
    ContractRules rules;
    rules.not_written_codes = not_written_codes();
    rules.drift_codes = drift;
    rules.max_flagged = 12; // 8 road features lose a part thinner than 1 cm (209)
    EXPECT_LE(flagged.size(), rules.max_flagged);
    const ContractReport contract = check_contract(input, output, problems, k_t, rules);
    EXPECT_TRUE(contract_holds(contract, k_t));
}

} // namespace
} // namespace trisnap::test
