// The collapse guard (issue 14): a run that would drop much of a layer stops before writing
// (exit 2, nothing at OUT, the tolerance it probably meant named); --allow-collapse, --force or
// [run] allow_collapse write it anyway; a few collapsed features run as before. Features smaller
// than the tolerance are counted while the input is read, so such a run stops before snapping
// (snap, plan and validate alike); slivers the envelopes cannot see stop after snapping, before
// OUT is committed (snap and a cluster `stitch`).
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace trisnap::test {
namespace {

/// `n` axis-aligned squares of side `size`, `step` apart along x from (x0, y0).
std::vector<FixtureFeature> squares(int n, double x0, double y0, double size, double step)
{
    std::vector<FixtureFeature> out;
    for (int i = 0; i < n; ++i) {
        const double x = x0 + i * step;
        const double x1 = x + size;
        const double y1 = y0 + size;
        char wkt[256];
        std::snprintf(wkt, sizeof wkt, "POLYGON ((%.9f %.9f,%.9f %.9f,%.9f %.9f,%.9f %.9f,%.9f %.9f))", x, y0, x1, y0, x1,
                      y1, x, y1, x, y0);
        out.push_back({wkt, {{"id", std::to_string(out.size() + 1)}}});
    }
    return out;
}

std::vector<FixtureFeature> operator+(std::vector<FixtureFeature> a, const std::vector<FixtureFeature>& b)
{
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

class CliCollapse : public ::testing::Test {
protected:
    /// 20 buildings of about 8 x 11 m near Andorra (EPSG:4326): all vanish at --tolerance 0.01.
    std::string buildings()
    {
        const std::string path = dir.path("buildings.gpkg");
        write_fixture(path, "GPKG", "buildings", 4326, wkbPolygon, squares(20, 1.5, 42.5, 0.0001, 0.001));
        return path;
    }

    /// 20 squares of 10 m in EPSG:3857, `tiny` of them 5 mm wide (they vanish at t = 0.01).
    std::string parcels(int tiny)
    {
        const std::string path = dir.path("parcels.gpkg");
        write_fixture(path, "GPKG", "parcels", 3857, wkbPolygon,
                      squares(20 - tiny, 0, 0, 10, 20) + squares(tiny, 0, 100, 0.005, 20));
        return path;
    }

    /// 20 squares of 10 m in EPSG:3857, `thin` of them slivers 10 m long and 5 mm wide: longer
    /// than the tolerance (the pre-check cannot see them), gone when snapped at t = 0.01.
    std::string slivers(int thin)
    {
        std::vector<FixtureFeature> features = squares(20 - thin, 0, 0, 10, 20);
        for (int i = 0; i < thin; ++i) {
            const double x = i * 20.0;
            char wkt[256];
            std::snprintf(wkt, sizeof wkt, "POLYGON ((%.3f 100,%.3f 100,%.3f 100.005,%.3f 100.005,%.3f 100))", x, x + 10,
                          x + 10, x, x);
            features.push_back({wkt, {{"id", std::to_string(features.size() + 1)}}});
        }
        const std::string path = dir.path("slivers.gpkg");
        write_fixture(path, "GPKG", "parcels", 3857, wkbPolygon, features);
        return path;
    }

    TempDir dir;
};

TEST_F(CliCollapse, TheOldReadmeExampleStopsBeforeWritingAndNamesTheMetres)
{
    const std::string out = dir.path("snapped.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", buildings(), out, "--tolerance", "0.01", "--report", dir.path("r.json")});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("trisnap: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("at least 20 of 20 features are smaller than the tolerance"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.01 (0.01 m = "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Stopped; --allow-collapse"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
    EXPECT_FALSE(exists(dir.path("r.json")));
    EXPECT_TRUE(leftovers(dir.path("")).empty());
}

TEST_F(CliCollapse, StdoutGetsNoFeatureEither)
{
    // The pre-check stops the run after the read, before the stream's header is out.
    const RunOutput r = run_trisnap(dir, {"snap", buildings(), "-", "--tolerance", "0.01", "--force"});
    ASSERT_EQ(r.code, 0) << r.err;
    const RunOutput stopped = run_trisnap(dir, {"snap", buildings(), "-", "--tolerance", "0.01"});
    EXPECT_EQ(stopped.code, 2) << stopped.err;
    EXPECT_EQ(stopped.out, "");
    // What the pre-check cannot see stops after snapping: the header (written when the driver
    // is opened, before snapping) and no feature.
    const RunOutput thin = run_trisnap(dir, {"snap", slivers(3), "-", "--tolerance", "0.01"});
    EXPECT_EQ(thin.code, 2) << thin.err;
    EXPECT_NE(thin.out.find("FeatureCollection"), std::string::npos) << thin.out;
    EXPECT_EQ(thin.out.find("\"Feature\""), std::string::npos) << thin.out;
}

TEST_F(CliCollapse, AllowCollapseWritesAndForceIsTheSame)
{
    const std::string in = buildings();
    const RunOutput a = run_trisnap(dir, {"snap", in, dir.path("a.gpkg"), "--tolerance", "0.01", "--allow-collapse",
                                          "--report", dir.path("a.json")});
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_TRUE(read_layer(dir.path("a.gpkg")).empty());
    const nlohmann::json j = read_json(dir.path("a.json"));
    EXPECT_EQ(j["problems_by_code"]["201"]["count"], 20) << j.dump(1);
    const RunOutput f = run_trisnap(dir, {"snap", in, dir.path("f.gpkg"), "--tolerance", "0.01", "--force"});
    ASSERT_EQ(f.code, 0) << f.err;
    EXPECT_EQ(file_bytes(dir.path("a.gpkg")), file_bytes(dir.path("f.gpkg")));
}

TEST_F(CliCollapse, TheSuggestedMetresKeepEveryFeature)
{
    const RunOutput r = run_trisnap(dir, {"snap", buildings(), dir.path("m.gpkg"), "--tolerance-m", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_layer(dir.path("m.gpkg")).size(), 20u);
}

TEST_F(CliCollapse, ConfigKeyAllowsIt)
{
    const std::string settings = dir.path("allow.toml");
    std::ofstream(settings) << "[run]\nallow_collapse = true\n";
    RunOutput r = run_trisnap(dir, {"snap", buildings(), dir.path("c.gpkg"), "--tolerance", "0.01", "--settings", settings});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(exists(dir.path("c.gpkg")));
    r = run_trisnap(dir, {"snap", "--settings", settings, "--print-config"});
    EXPECT_NE(r.out.find("allow_collapse = true"), std::string::npos) << r.out;
}

TEST_F(CliCollapse, UnderATenthRunsAsBefore)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", parcels(1), out, "--tolerance", "0.01", "--report", dir.path("r.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_layer(out).size(), 19u);
    EXPECT_EQ(read_json(dir.path("r.json"))["problems_by_code"]["201"]["count"], 1);
}

TEST_F(CliCollapse, OverATenthInLayerUnitsStops)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", parcels(3), out, "--tolerance", "0.01"});
    expect_error(r, 2, "at least 3 of 20 features are smaller than the tolerance: snapping would drop them; the "
                       "tolerance is 0.01 m: give a smaller one");
    EXPECT_FALSE(exists(out));
}

TEST_F(CliCollapse, SliversThePreCheckCannotSeeStopAfterSnapping)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", slivers(3), out, "--tolerance", "0.01"});
    expect_error(r, 2, "snapping would drop 3 of 20 features (collapsed); the tolerance is 0.01 m: give a smaller one. "
                       "Nothing was written");
    EXPECT_FALSE(exists(out));
    const RunOutput v = run_trisnap(dir, {"validate", slivers(3), out, "--tolerance", "0.01"});
    EXPECT_EQ(v.code, 0) << v.err;
    EXPECT_NE(v.out.find("collapse:  at least 0 of 20 features vanish"), std::string::npos) << v.out;
}

TEST_F(CliCollapse, AnyCollapseWithDegreesAboveTheWarningStops)
{
    // 19 fields of ~1 km survive 0.001 degrees; the one 50 m square does not: 5 %, but in degrees.
    const std::string in = dir.path("fields.gpkg");
    write_fixture(in, "GPKG", "fields", 4326, wkbPolygon,
                  squares(19, 1.5, 42.5, 0.01, 0.02) + squares(1, 1.5, 43.0, 0.0005, 0.02));
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.001"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("at least 1 of 20 features are smaller than the tolerance"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.001"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
}

TEST_F(CliCollapse, ValidatePredictsIt)
{
    const std::string in = buildings();
    RunOutput r = run_trisnap(dir, {"validate", in, dir.path("v.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("at least 20 of 20 features are smaller than the tolerance"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.01"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"validate", in, dir.path("v.gpkg"), "--tolerance", "0.01", "--force"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("collapse:  at least 20 of 20 features vanish"), std::string::npos) << r.out;
    r = run_trisnap(dir, {"validate", in, dir.path("v.gpkg"), "--tolerance-m", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("collapse:  at least 0 of 20 features vanish"), std::string::npos) << r.out;
}

TEST_F(CliCollapse, ClusterStitchStopsToo)
{
    // plan reads the input: the pre-check stops it there, before any task is submitted.
    const std::string run_dir = dir.path("run");
    RunOutput r = run_trisnap(dir, {"plan", buildings(), dir.path("stopped"), "--tolerance", "0.01", "-q"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("at least 20 of 20 features are smaller than the tolerance"), std::string::npos) << r.err;
    // Slivers it cannot see stop the stitch.
    r = run_trisnap(dir, {"plan", slivers(3), run_dir, "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string out = dir.path("out.gpkg");
    r = run_trisnap(dir, {"stitch", run_dir, out});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("snapping would drop 3 of 20 features (collapsed)"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
    r = run_trisnap(dir, {"stitch", run_dir, out, "--allow-collapse", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(exists(out));
}

TEST_F(CliCollapse, AndorraBuildingsAtOneHundredthOfADegree)
{
    const std::string in = data_dir() + "/osm_small_extracts/andorra_graphhopper_2013.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    const std::string out = dir.path("snapped.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--layer", "buildings", "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("at least 292 of 292 features are smaller than the tolerance"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.01"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
}

TEST_F(CliCollapse, TheReadmeFirstExampleWorksOnTheBundledSample)
{
    const std::string in = std::string(TRISNAP_CONFIGS_DIR) + "/../data/delft_partition_sample.gpkg";
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("snapped.gpkg"), "--tolerance", "0.01", "--report",
                                          dir.path("snapped.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_layer(dir.path("snapped.gpkg")).size(), 260u);
}

} // namespace
} // namespace trisnap::test

namespace trisnap::test {
namespace {

TEST_F(CliCollapse, RejectionsAreNamedAsSuchNotAsCollapses)
{
    // Features the engine rejects (109: a coordinate too large for the tolerance) were counted
    // and named as collapses, with advice about the tolerance's unit or size that could not help:
    // at t = 1e-12 the guard said "give a smaller one". They still count towards the share of
    // the layer lost, named as rejections, with what the engine takes.
    const std::string out = dir.path("out.gpkg");
    RunOutput r = run_trisnap(dir, {"snap", parcels(0), out, "--tolerance", "1e-12"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("snapping would drop 19 of 20 features (rejected: a coordinate too large for the tolerance "
                         "at double precision, problem 109); coordinates beyond 17.5922 cannot be snapped"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("collapsed"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("smaller"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
    // A degree tolerance above 0.001 stops a run for any collapse (metres typed as degrees), but a
    // rejection says nothing about the unit: one feature with a huge coordinate among 20 goes
    // through, reported, and the summary names it.
    const std::string in = dir.path("geo.gpkg");
    write_fixture(in, "GPKG", "parcels", 4326, wkbPolygon,
                  squares(20, 1.5, 42.5, 0.1, 0.2) + squares(1, 1e12, 42.5, 0.1, 0.2));
    r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.002", "--report", dir.path("r.json")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("1 dropped by the engine, 1 of them rejected (109 huge coordinate)"), std::string::npos) << r.out;
    EXPECT_EQ(read_json(dir.path("r.json"))["problems_by_code"]["109"]["count"], 1);
    EXPECT_EQ(read_layer(out).size(), 20u);
}

} // namespace
} // namespace trisnap::test
