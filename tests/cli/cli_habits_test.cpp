// What a user expects of the command line: "did you mean", --version with the libraries,
// --formats, plurals, -v/-vv, validate failing where snap would, the problems as a point layer
// and a warning when metres on a geographic layer are far off.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>

namespace trisnap::test {
namespace {

class CliHabits : public ::testing::Test {
protected:
    std::string fixture(const std::string& name = "in.gpkg") { return write_snapping_gpkg(dir, name); }

    TempDir dir;
};

TEST_F(CliHabits, MistypedCommandAndOptionNameTheClosest)
{
    expect_error(run_trisnap(dir, {"sanp", "a.gpkg"}), 2, "unknown command 'sanp'; did you mean snap?");
    expect_error(run_trisnap(dir, {"valdiate"}), 2, "did you mean validate?");
    expect_error(run_trisnap(dir, {"snap", "a.gpkg", "b.gpkg", "--tolerence", "1"}), 2,
                          "unknown option --tolerence for trisnap snap; did you mean --tolerance?");
    expect_error(run_trisnap(dir, {"info", "a.gpkg", "--layr", "x"}), 2, "did you mean --layer?");
    const RunOutput far = run_trisnap(dir, {"frobnicate"});
    EXPECT_EQ(far.code, 2);
    EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

TEST_F(CliHabits, VersionNamesTheLibraries)
{
    const RunOutput r = run_trisnap(dir, {"--version"});
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, "");
    for (const char* text : {"trisnap 0.", "GDAL 3.", "PROJ ", "CGAL 5.", "oneTBB 20"}) {
        EXPECT_NE(r.out.find(text), std::string::npos) << text << " in " << r.out;
    }
}

TEST_F(CliHabits, FormatsListsReadersWritersAndStreams)
{
    const RunOutput r = run_trisnap(dir, {"--formats"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\n  GPKG             rw-  GeoPackage (.gpkg)\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\n  GeoJSON          rws"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\n  FlatGeobuf       rws"), std::string::npos) << r.out;
}

TEST_F(CliHabits, CountsAreSingularForOne)
{
    const std::string in = dir.path("one.gpkg");
    write_fixture(in, "GPKG", "one", 3857, wkbPolygon, {{"POLYGON ((0 0,0.001 0,0.001 0.001,0 0.001,0 0))", {}}});
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("1 feature in, 0 written"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\n1 problem: 201"), std::string::npos) << r.out;
    r = run_trisnap(dir, {"info", in});
    EXPECT_NE(r.out.find("(GPKG), 1 layer\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 feature, 5 vertices"), std::string::npos) << r.out;
}

TEST_F(CliHabits, VerboseLogsOnStderr)
{
    RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "0.01", "-v"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("trisnap: info: input:"), std::string::npos) << r.err;
    // The time of every phase, with the peak memory after it.
    for (const char* phase : {"plan", "spool", "snap", "stitch", "write"}) {
        const std::regex timing(std::string("(^|\n)trisnap: info: ") + phase + R"(: [0-9]+\.[0-9]{2} s, peak memory )");
        EXPECT_TRUE(std::regex_search(r.err, timing)) << "no timing of phase " << phase << " in:\n" << r.err;
    }
    EXPECT_EQ(r.err.find("GDAL debug"), std::string::npos) << "GDAL's debug lines only at -vv";
    r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "0.01", "-vv", "--overwrite"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("trisnap: debug: GDAL debug: GDAL: GDALOpen("), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("trisnap:"), std::string::npos) << "logs never go to stdout";
}

// -v says how the heap's pages were chosen; a TRISNAP_HUGE_PAGES that is neither 0 nor 1 is a
// warning from any command, not an error, and the run goes on as without it.
TEST_F(CliHabits, HugePagesAreSaidAndAMistypedSettingWarned)
{
    RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "0.01", "-v"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::regex_search(r.err, std::regex(R"((^|\n)trisnap: info: memory:    heap in (huge|4 KiB) pages \()"))) << r.err;
    EXPECT_EQ(r.err.find("TRISNAP_HUGE_PAGES"), std::string::npos) << r.err;
    const std::string counts = r.out.substr(0, r.out.find('\n')); // "6 features in, 5 written, ..."
    EXPECT_NE(counts.find("6 features in, 5 written"), std::string::npos) << r.out;
    {
        const ScopedEnv off("TRISNAP_HUGE_PAGES", "0");
        r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "0.01", "-v", "--overwrite"});
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("trisnap: info: memory:    heap in 4 KiB pages (TRISNAP_HUGE_PAGES=0)"), std::string::npos) << r.err;
    }
    const ScopedEnv mistyped("TRISNAP_HUGE_PAGES", "yes");
    r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "0.01", "--overwrite"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("trisnap: warning: TRISNAP_HUGE_PAGES=yes is neither 0 nor 1: ignored"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')), counts); // as without it
    r = run_trisnap(dir, {"info", fixture()}); // every command says it, not only snap
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("trisnap: warning: TRISNAP_HUGE_PAGES=yes is neither 0 nor 1: ignored"), std::string::npos) << r.err;
}

TEST_F(CliHabits, ValidateFailsWhereSnapWouldBeforeSnapping)
{
    const std::string in = dir.path("polygons.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon,
                  {{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "1"}}}, {"POLYGON ((2 0,3 0,3 1,2 1,2 0))", {{"id", "2"}}}});
    for (const char* command : {"validate", "snap"}) {
        expect_error(run_trisnap(dir, {command, in, dir.path("o.gpkg"), "--tolerance", "1", "--where", "id > 100"}),
                              1, "no feature matches --where/--bbox");
        expect_error(run_trisnap(dir, {command, in, dir.path("o.gpx"), "--tolerance", "1"}), 2,
                              "o.gpx: the GPX driver refuses it: cannot create layer 'parcels' of type Polygon");
        expect_error(run_trisnap(dir, {command, in, dir.path("o.gpkg"), "--tolerance", "1", "--report",
                                                dir.path("nowhere/r.json")}), 2, "does not exist");
        expect_error(run_trisnap(dir, {command, in, dir.path("o.gpkg"), "--tolerance", "1", "--problems-layer",
                                                dir.path("p.txt")}), 2, "give a .gpkg or .geojson file name");
    }
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "1", "--problems-layer",
                                   dir.path("o.gpkg")}), 2, "--problems-layer " + dir.path("o.gpkg") + ": is a file of OUT");
    expect_error(run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--tolerance", "1", "--report", dir.path("r.json"),
                                   "--problems-layer", dir.path("./r.json")}), 2, "--report and --problems-layer are the same file");
    EXPECT_FALSE(exists(dir.path("o.gpx")));
    EXPECT_FALSE(exists(dir.path("o.gpkg")));
}

/// The problems layer against the report: same problems, points where the report has x/y.
void check_problems_layer(const std::string& layer_path, const nlohmann::json& report)
{
    const std::vector<ReadFeature> points = read_layer(layer_path, "problems");
    ASSERT_EQ(points.size(), report["problems"].size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const nlohmann::json& p = report["problems"][i];
        EXPECT_EQ(points[i].fields.at("fid"), std::to_string(p["fid"].get<std::int64_t>()));
        EXPECT_EQ(points[i].fields.at("code"), std::to_string(p["code"].get<int>()));
        EXPECT_EQ(points[i].fields.at("name"), p["name"].get<std::string>());
        EXPECT_EQ(points[i].fields.at("message"), p["message"].get<std::string>());
        EXPECT_EQ(points[i].has_geometry, !p["x"].is_null()) << p.dump();
        if (points[i].has_geometry) {
            OGRGeometry* g = nullptr;
            OGRGeometryFactory::createFromWkt(points[i].wkt.c_str(), nullptr, &g);
            ASSERT_NE(g, nullptr);
            EXPECT_DOUBLE_EQ(g->toPoint()->getX(), p["x"].get<double>());
            EXPECT_DOUBLE_EQ(g->toPoint()->getY(), p["y"].get<double>());
            OGRGeometryFactory::destroyGeometry(g);
        }
    }
}

TEST_F(CliHabits, ProblemsLayerAsGeoPackageAndGeoJson)
{
    std::vector<FixtureFeature> features = snapping_fixture();
    features.push_back({"", {{"id", "7"}}}); // null geometry: a problem without a place
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, features);
    for (const char* name : {"p.gpkg", "p.geojson"}) {
        const std::string layer = dir.path(name);
        const std::string report = dir.path("r.json");
        const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--overwrite",
                                              "--report", report, "--problems-layer", layer, "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
        const nlohmann::json j = read_json(report);
        ASSERT_GE(j["problems"].size(), 2u) << j.dump(1);
        check_problems_layer(layer, j);
        GDALDatasetUniquePtr ds(GDALDataset::Open(layer.c_str(), GDAL_OF_VECTOR));
        ASSERT_TRUE(ds);
        const OGRSpatialReference* srs = ds->GetLayer(0)->GetSpatialRef();
        ASSERT_NE(srs, nullptr) << name;
        EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "3857") << name;
        const RunOutput again = run_trisnap(dir, {"snap", in, dir.path("o2.gpkg"), "--tolerance", "0.01",
                                                  "--problems-layer", layer});
        EXPECT_EQ(again.code, 2) << "an existing problems layer needs --overwrite";
    }
}

TEST_F(CliHabits, MetresOnAWorldLayerWarn)
{
    const std::string world = dir.path("world.gpkg");
    write_fixture(world, "GPKG", "world", 4326, wkbPolygon,
                  {{"POLYGON ((-170 -60,170 -60,170 70,-170 70,-170 -60))", {}}});
    RunOutput r = run_trisnap(dir, {"validate", world, dir.path("o.gpkg"), "--tolerance-m", "100"});
    EXPECT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("trisnap: warning: --tolerance-m 100: the layer spans latitudes -60.0 to 70.0"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("more than 10 % off"), std::string::npos) << r.err;
    const std::string city = dir.path("city.gpkg");
    write_fixture(city, "GPKG", "city", 4326, wkbPolygon, {{"POLYGON ((4 52,4.2 52,4.2 52.2,4 52.2,4 52))", {}}});
    r = run_trisnap(dir, {"validate", city, dir.path("o.gpkg"), "--tolerance-m", "100"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
}

TEST_F(CliHabits, NaturalEarthCountriesWarn)
{
    const std::string path = data_dir() + "/natural_earth/natural_earth.gpkg";
    if (!exists(path)) {
        GTEST_SKIP() << "data set absent: " << path;
    }
    const RunOutput r = run_trisnap(dir, {"validate", path, dir.path("o.gpkg"), "--layer", "ne_50m_admin_0_countries",
                                          "--tolerance-m", "100"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("converted at -3.2"), std::string::npos) << r.err;
}

} // namespace
} // namespace trisnap::test
