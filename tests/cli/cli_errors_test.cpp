// One message and one exit code per bad input; clean stdout/stderr on success.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>

namespace trisnap::test {
namespace {

class CliErrors : public ::testing::Test {
protected:
    std::string fixture(const std::string& name = "in.gpkg") { return write_snapping_gpkg(dir, name); }

    TempDir dir;
};

TEST_F(CliErrors, ProblemsListsTheCatalogue)
{
    const RunOutput r = run_trisnap(dir, {"problems"});
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("201  collapsed_polygon"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("106  non_finite_coordinate"), std::string::npos) << r.out;
}

TEST_F(CliErrors, InfoDescribesTheLayer)
{
    const RunOutput r = run_trisnap(dir, {"info", fixture()});
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("layer 'parcels'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("6 features, 40 vertices"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("EPSG:3857"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("extent:"), std::string::npos) << r.out;
}

TEST_F(CliErrors, SuccessIsQuietOnStderr)
{
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("6 features in"), std::string::npos) << r.out;
}

TEST_F(CliErrors, JsonProgressLinesOnStderr)
{
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg"), "--tolerance", "0.01",
                                          "--json-progress", "--progress", "never", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "");
    std::set<std::string> finished;
    std::map<std::string, std::int64_t> last;
    for (const std::string& line : r.err_lines()) {
        const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        ASSERT_FALSE(j.is_discarded()) << "not JSON: " << line;
        const std::string phase = j["phase"].get<std::string>();
        const std::int64_t done = j["done"].get<std::int64_t>();
        EXPECT_GE(done, last[phase]) << "counts go backwards: " << line;
        last[phase] = done;
        ASSERT_TRUE(j.contains("unit") && j.contains("eta_s")) << line;
        if (phase == "snap") {
            // Input vertices, with a total known from the start (not tiles called features).
            EXPECT_EQ(j["unit"], "vertices") << line;
            EXPECT_GT(j["total"].get<std::int64_t>(), 0) << line;
        }
        if (phase == "stitch") {
            // Tiles checked at seams, of the tiles there are (one here).
            EXPECT_EQ(j["unit"], "tiles") << line;
            EXPECT_EQ(j["total"].get<std::int64_t>(), 1) << line;
        }
        if (phase == "plan" || phase == "spool" || phase == "write") {
            // Features read, features spooled (two passes counted once), features written.
            EXPECT_EQ(j["unit"], phase == "write" ? "features written" : "features") << line;
            EXPECT_EQ(j["total"].get<std::int64_t>(), 6) << line;
        }
        if (j["finished"].get<bool>()) {
            finished.insert(phase);
            // The write phase ends at what was written: the 0.005 square collapsed.
            EXPECT_EQ(done, phase == "write" ? 5 : j["total"].get<std::int64_t>()) << line;
        }
    }
    EXPECT_EQ(finished, (std::set<std::string>{"plan", "spool", "snap", "stitch", "write"}));
}

TEST_F(CliErrors, MissingFile)
{
    expect_error(run_trisnap(dir, {"snap", dir.path("nope.gpkg"), dir.path("out.gpkg"), "--tolerance", "1"}), 1,
                 "no such file");
}

TEST_F(CliErrors, CorruptFile)
{
    const std::string path = dir.path("corrupt.gpkg");
    std::ofstream(path) << "this is not a geopackage at all";
    expect_error(run_trisnap(dir, {"snap", path, dir.path("out.gpkg"), "--tolerance", "1"}), 1, "corrupt.gpkg");
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
}

TEST_F(CliErrors, UnknownLayerListsTheLayers)
{
    expect_error(run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg"), "--tolerance", "1", "--layer", "roads"}),
                 2, "no layer 'roads'; layers: parcels");
}

TEST_F(CliErrors, ToleranceMustBePositiveAndFinite)
{
    for (const char* t : {"0", "-1", "nan", "inf"})
        expect_error(run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg"), "--tolerance", t}), 2,
                     "tolerance must be finite and > 0");
    expect_error(run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg")}), 2, "no tolerance");
}

TEST_F(CliErrors, UnsupportedGeometryType)
{
    const std::string path = dir.path("points.gpkg");
    write_fixture(path, "GPKG", "points", 3857, wkbPoint, {{"POINT (1 2)", {}}});
    expect_error(run_trisnap(dir, {"snap", path, dir.path("out.gpkg"), "--tolerance", "1"}), 1,
                 "unsupported geometry type Point");
}

TEST_F(CliErrors, EmptyLayer)
{
    const std::string path = dir.path("empty.gpkg");
    write_fixture(path, "GPKG", "nothing", 3857, wkbPolygon, {});
    expect_error(run_trisnap(dir, {"snap", path, dir.path("out.gpkg"), "--tolerance", "1"}), 1, "the layer is empty");
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
}

TEST_F(CliErrors, ExistingOutputNeedsOverwrite)
{
    const std::string in = fixture();
    const std::string out = dir.path("out.gpkg");
    std::ofstream(out) << "keep me";
    expect_error(run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01"}), 2, "add --overwrite");
    EXPECT_EQ(file_bytes(out), "keep me");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--overwrite", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(read_layer(out).empty());
}

TEST_F(CliErrors, BadFiltersAndFormats)
{
    const std::string in = fixture();
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "1", "--bbox", "1,2,3"}), 2, "--bbox");
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "1", "--where", "nonsense ==="}), 2,
                 "--where");
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.xyz"), "--tolerance", "1"}), 2, "give one with -f");
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "1", "-f", "NoSuchDriver"}), 2,
                 "unknown GDAL format");
    expect_error(run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "1", "--where", "id > 100"}), 1,
                 "no feature matches");
}

TEST_F(CliErrors, NullAndEmptyGeometriesAreProblemsNotErrors)
{
    const std::string in = dir.path("nulls.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown,
                  {{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "1"}}}, {"", {{"id", "2"}}},
                   {"POLYGON EMPTY", {{"id", "3"}}}});
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = read_json(report);
    EXPECT_EQ(j["problems_by_code"]["107"]["count"], 2) << j.dump(1);
    EXPECT_EQ(read_layer(out).size(), 3u); // attributes kept, geometry still null/empty
    r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--overwrite", "--strict", "-q"});
    EXPECT_EQ(r.code, 3);
    EXPECT_EQ(r.err, "");
}

TEST_F(CliErrors, CurvesZAndCollections)
{
    const std::string in = dir.path("kinds.gpkg");
    write_fixture(in, "GPKG", "kinds", 3857, wkbUnknown,
                  {{"CURVEPOLYGON (CIRCULARSTRING (0 0,10 0,10 10,0 10,0 0))", {{"id", "1"}}},
                   {"POLYGON Z ((20 0 1,30 0 2,30 10 3,20 10 4,20 0 1))", {{"id", "2"}}},
                   {"GEOMETRYCOLLECTION (POINT (50 50),LINESTRING (60 60,70 70))", {{"id", "3"}}},
                   {"MULTILINESTRING ((0 -5,10 -5),(0 -10,10 -10))", {{"id", "4"}}}});
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = read_json(report);
    ASSERT_EQ(j["problems_by_code"]["108"]["count"], 1) << j.dump(1);
    const auto features = read_layer(out);
    ASSERT_EQ(features.size(), 4u);
    EXPECT_EQ(features[0].wkt.rfind("POLYGON ((", 0), 0u) << features[0].wkt; // linearised
    EXPECT_NE(features[1].wkt.find("30 10 3"), std::string::npos) << features[1].wkt; // Z kept
    EXPECT_EQ(features[2].wkt, "GEOMETRYCOLLECTION (POINT (50 50),LINESTRING (60 60,70 70))");
    EXPECT_EQ(features[3].wkt.rfind("MULTILINESTRING", 0), 0u) << features[3].wkt;
    for (const auto& f : features) EXPECT_TRUE(f.valid) << f.wkt;
}

TEST_F(CliErrors, NonFiniteCoordinatesAreRejectedAndReported)
{
    const std::string in = dir.path("nan.gpkg");
    FixtureFeature bad{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "2"}}, true};
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon,
                  {{"POLYGON ((5 5,6 5,6 6,5 6,5 5))", {{"id", "1"}}}, bad});
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
    EXPECT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(report);
    ASSERT_EQ(j["problems"].size(), 1u) << j.dump(1);
    EXPECT_EQ(j["problems"][0]["code"], 106);
    EXPECT_EQ(j["problems"][0]["fid"], 2);
    const auto features = read_layer(out);
    EXPECT_EQ(features.size(), 1u);
    EXPECT_EQ(missing_but_reported(j, features), std::vector<std::int64_t>{2});
}

TEST_F(CliErrors, HugeCoordinatesAreReportedNotFatal)
{
    const std::string in = dir.path("huge.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon,
                  {{"POLYGON ((0 0,10 0,10 10,0 10,0 0))", {{"id", "1"}}},
                   {"POLYGON ((1e300 0,1.0000001e300 0,1e300 1e300,1e300 0))", {{"id", "2"}}}});
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = read_json(report);
    EXPECT_EQ(j["problems_by_code"]["109"]["count"], 1) << j.dump(1);
    const auto features = read_layer(out);
    EXPECT_EQ(features.size() + missing_but_reported(j, features).size(), 2u);
}

TEST_F(CliErrors, ValidateWritesNothing)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"validate", fixture(), out, "--tolerance", "0.01", "--report", dir.path("r.json")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("layer 'parcels', 6 features"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("validate: ok, nothing written"), std::string::npos) << r.out;
    EXPECT_FALSE(exists(out));
    EXPECT_FALSE(exists(dir.path("r.json")));
}

TEST_F(CliErrors, GeographicToleranceInMetres)
{
    const std::string in = dir.path("geo.gpkg");
    write_fixture(in, "GPKG", "parcels", 4326, wkbPolygon, {{"POLYGON ((10 60,10.001 60,10.001 60.001,10 60.001,10 60))", {}}});
    RunOutput r = run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--tolerance-m", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("at mean latitude 60.0005"), std::string::npos) << r.out;
    // 0.01 degrees is over a kilometre: the warning, then the collapse guard refuses the run it predicts.
    r = run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("trisnap: warning: --tolerance 0.01 is in degrees"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.01"), std::string::npos) << r.err;
}

TEST_F(CliErrors, FailedRunLeavesNothingBehind)
{
    // A run that fails after planning must leave neither OUT nor a temporary directory behind.
    const std::string in = dir.path("empty.gpkg");
    write_fixture(in, "GPKG", "nothing", 3857, wkbPolygon, {});
    run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "1"});
    for (const auto& entry : std::filesystem::directory_iterator(dir.path("")))
        EXPECT_EQ(entry.path().filename().string().find(".trisnap-tmp"), std::string::npos);
}

} // namespace
} // namespace trisnap::test
