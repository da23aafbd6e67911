// Never lose data: the input is never written, OUT and the report appear whole or not at all,
// a full disk is an error (exit 1, nothing at OUT), and nothing temporary is left behind.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace trisnap::test {
namespace {
namespace fs = std::filesystem;

/// `n` separate 24-gons with a name each: about 1 MB as GeoJSON, 0.4 MB as GPKG.
std::vector<FixtureFeature> many_polygons(int n, double scale = 1.0)
{
    std::vector<FixtureFeature> features;
    for (int k = 0; k < n; ++k) {
        const double cx = (k % 40) * 10.0 * scale;
        const double cy = (k / 40) * 10.0 * scale;
        std::string wkt = "POLYGON ((";
        for (int i = 0; i <= 24; ++i) {
            const double a = 2 * 3.14159265358979 * (i % 24) / 24;
            wkt += (i ? "," : "") + std::to_string(cx + 3 * scale * std::cos(a)) + " " +
                   std::to_string(cy + 3 * scale * std::sin(a));
        }
        features.push_back({wkt + "))", {{"id", std::to_string(k)}, {"name", "polygon " + std::to_string(k)}}});
    }
    return features;
}

/// x, y of the exterior ring of the first feature, as stored (no text in between).
std::vector<double> ring_coordinates(const std::string& path)
{
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    OGRFeatureUniquePtr f(ds->GetLayer(0)->GetNextFeature());
    std::vector<double> out;
    for (const OGRPoint& p : *f->GetGeometryRef()->toPolygon()->getExteriorRing()) {
        out.push_back(p.getX());
        out.push_back(p.getY());
    }
    return out;
}

class CliSafety : public ::testing::Test {
protected:
    std::string fixture(const std::string& name = "in.gpkg", const std::string& driver = "GPKG")
    {
        const std::string path = dir.path(name);
        write_fixture(path, driver, "parcels", 3857, wkbUnknown, snapping_fixture());
        return path;
    }

    void expect_no_leftovers() { EXPECT_EQ(leftovers(dir.path("")), std::vector<std::string>{}); }

    TempDir dir;
};

TEST_F(CliSafety, ReportNamingTheInputUnderAnyNameIsRefused)
{
    const std::string in = fixture();
    const std::string before = file_bytes(in);
    fs::create_hard_link(in, dir.path("hard.json"));
    fs::create_symlink(in, dir.path("soft.json"));
    for (const std::string report : {in, dir.path("hard.json"), dir.path("soft.json"), dir.path("./x/../in.gpkg")}) {
        fs::create_directories(dir.path("x"));
        const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report});
        expect_error(r, 2, "is a file of the input");
        EXPECT_EQ(file_bytes(in), before) << report;
        EXPECT_FALSE(exists(dir.path("out.gpkg")));
    }
}

TEST_F(CliSafety, ReportNamingOutIsRefused)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), out, "--tolerance", "0.01", "--report", out});
    expect_error(r, 2, "is a file of OUT");
    EXPECT_FALSE(exists(out));
    expect_no_leftovers();
}

TEST_F(CliSafety, OutThatWouldReplaceAFileOfTheInputShapefileIsRefused)
{
    const std::string in = fixture("v.shp", "ESRI Shapefile");
    std::map<std::string, std::string> before;
    for (const char* ext : {".shp", ".shx", ".dbf", ".prj"}) {
        before[ext] = file_bytes(dir.path(std::string("v") + ext));
    }
    fs::create_directory_symlink(dir.path(""), dir.path("same"));
    for (const char* out : {"v.dbf", "same/v.dbf", "same/v.shp"}) {
        const RunOutput r = run_trisnap(dir, {"snap", in, dir.path(out), "--tolerance", "0.01", "--overwrite"});
        expect_error(r, 2, "the input");
    }
    for (const auto& [ext, bytes] : before) {
        EXPECT_EQ(file_bytes(dir.path("v" + ext)), bytes) << ext;
    }
    expect_no_leftovers();
}

TEST_F(CliSafety, FailedLayerOrFieldCreationLeavesNoTemporaryDirectory)
{
    const std::string in = fixture();
    const std::vector<std::vector<std::string>> cases = {
        {dir.path("out.gpkg"), "-nln", "gpkg_contents"}, // a reserved table name
        {dir.path("out.gpkg"), "--lco", "FID=name"},     // the FID column clashes with a String field
        {dir.path("out.gpx")},                           // GPX holds no polygons
    };
    for (const auto& extra : cases) {
        std::vector<std::string> args{"snap", in};
        args.insert(args.end(), extra.begin(), extra.end());
        args.insert(args.end(), {"--tolerance", "0.01"});
        expect_error(run_trisnap(dir, args), 2, extra[0]); // refused when the output is tried, before reading
        EXPECT_FALSE(exists(extra[0]));
        expect_no_leftovers();
    }
}

TEST_F(CliSafety, StaleTemporaryDirectoriesOfDeadRunsAreRemoved)
{
    const pid_t dead = fork();
    if (dead == 0) {
        _exit(0);
    }
    waitpid(dead, nullptr, 0);
    const std::string stale = dir.path(".out.gpkg.trisnap-tmp-" + std::to_string(dead));
    const std::string alive = dir.path(".out.gpkg.trisnap-tmp-" + std::to_string(getpid()));
    fs::create_directories(stale + "/sub");
    fs::create_directories(alive);
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("out.gpkg"), "--tolerance", "0.01", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(exists(stale)) << "the directory of a process that is gone is removed";
    EXPECT_TRUE(exists(alive)) << "a live process's directory is left alone";
}

TEST_F(CliSafety, OutCreatedByAnotherProcessDuringTheRunIsNotReplaced)
{
    const std::string in = dir.path("many.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon, many_polygons(1500));
    const std::string out = dir.path("out.geojson");
    const pid_t pid = spawn_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-q"});
    // Stop the run while its temporary directory exists (it is writing), create OUT, go on.
    bool stopped = false;
    for (int i = 0; i < 200000 && !stopped; ++i) {
        if (!leftovers(dir.path("")).empty()) {
            stopped = kill(pid, SIGSTOP) == 0;
        } else {
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
    const bool window_missed = exists(out);
    if (!window_missed) {
        std::ofstream(out) << "keep me";
    }
    kill(pid, SIGCONT);
    const RunOutput r = wait_trisnap(dir, pid);
    if (!stopped || window_missed) {
        GTEST_SKIP() << "the run finished before it could be stopped while writing";
    }
    expect_error(r, 2, "already exists");
    EXPECT_EQ(file_bytes(out), "keep me");
    expect_no_leftovers();
}

/// A full disk for every format: RLIMIT_FSIZE makes writes past 192 KiB fail like ENOSPC.
class CliDiskFull : public ::testing::TestWithParam<std::string> {
protected:
    TempDir dir;
};

TEST_P(CliDiskFull, LeavesNothingAtOutAndExits1)
{
    // KML and GeoJSONSeq store WGS84 lon/lat only and refuse a layer in another CRS
    // (io/format_limits.hpp): for them a layer without a CRS (a Shapefile without .prj), at
    // coordinates that are valid longitudes and latitudes, which they write as they are.
    const bool wgs84_only = GetParam() == "kml" || GetParam() == "geojsons";
    const std::string in = dir.path(wgs84_only ? "many.shp" : "many.gpkg");
    write_fixture(in, wgs84_only ? "ESRI Shapefile" : "GPKG", "parcels", wgs84_only ? 0 : 3857, wkbPolygon,
                  many_polygons(1000, wgs84_only ? 0.1 : 1.0));
    const std::string out = dir.path("out." + GetParam());
    const std::vector<std::string> args{"snap", in, out, "--tolerance", "0.01", "-q"};
    const RunOutput r = run_trisnap_limited(dir, args, Limits{192 * 1024, 0});
    expect_error(r, 1, "cannot write");
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << "the limit is what failed: " << r.err;
    for (const auto& entry : fs::directory_iterator(dir.path(""))) {
        EXPECT_NE(entry.path().stem().string(), "out") << "left at OUT: " << entry.path();
    }
    EXPECT_EQ(leftovers(dir.path("")), std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(Formats, CliDiskFull,
                         ::testing::Values("geojson", "geojsons", "gml", "kml", "gpkg", "shp", "fgb"));

TEST_F(CliSafety, ReportThatIsADirectoryOrADeviceIsRefusedBeforeAnythingIsWritten)
{
    const std::string in = fixture();
    const std::string out = dir.path("out.gpkg");
    fs::create_directories(dir.path("reports"));
    expect_error(run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", dir.path("reports")}), 2,
                 "is a directory");
    expect_error(run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", "/dev/full"}), 2,
                 "not a regular file");
    EXPECT_FALSE(exists(out));
    expect_no_leftovers();
}

TEST_F(CliSafety, ReportThatCannotBeWrittenLeavesNoOutEither)
{
    // Many null geometries: each a problem in the report, a short line in OUT.
    std::vector<FixtureFeature> features{{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "0"}}}};
    for (int i = 1; i < 2000; ++i) {
        features.push_back({"", {{"id", std::to_string(i)}}});
    }
    const std::string in = dir.path("nulls.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon, features);
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("report.json");
    const std::vector<std::string> args{"snap", in, out, "--tolerance", "0.01", "--report", report, "-q"};
    ASSERT_EQ(run_trisnap(dir, args).code, 0);
    const auto out_size = static_cast<long long>(fs::file_size(out));
    const auto report_size = static_cast<long long>(fs::file_size(report));
    ASSERT_GT(report_size, out_size * 3 / 2) << "the fixture must make the report the larger file";
    fs::remove(out);
    fs::remove(report);
    const RunOutput r = run_trisnap_limited(dir, args, Limits{(out_size + report_size) / 2, 0});
    expect_error(r, 1, "report.json");
    EXPECT_FALSE(exists(out)) << "OUT and the report are decided together";
    EXPECT_FALSE(exists(report));
    expect_no_leftovers();
}

TEST_F(CliSafety, FileNamesThatAreNotUtf8StillGiveAReport)
{
    const std::string in = dir.path("in\xff.gpkg");
    fs::copy_file(fixture(), in);
    const std::string report = dir.path("report\xfe.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = read_json(report);
    ASSERT_TRUE(j.is_object());
    EXPECT_NE(j["input"]["path"].get<std::string>().find("in\xEF\xBF\xBD.gpkg"), std::string::npos)
        << "a byte that is not UTF-8 becomes U+FFFD";
}

TEST_F(CliSafety, FormatsThatWriteNoFileOrNoGeometryAreRefused)
{
    const std::string in = fixture();
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out"), "-f", "Memory", "--tolerance", "0.01"}), 2,
                 "writes no file");
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out.xlsx"), "--tolerance", "0.01"}), 2,
                 "cannot store the geometries");
    EXPECT_FALSE(exists(dir.path("out.xlsx")));
    expect_no_leftovers();
}

TEST_F(CliSafety, CsvKeepsTheGeometriesAsWktToTheLastBit)
{
    const std::string out = dir.path("out.csv");
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), out, "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto features = read_layer(out);
    ASSERT_EQ(features.size(), 5u); // the 6th collapses at t = 0.01
    for (const ReadFeature& f : features) {
        EXPECT_TRUE(f.has_geometry) << "orig_fid " << f.fields.at("orig_fid");
        EXPECT_TRUE(f.valid) << f.wkt;
    }
    // A coordinate that needs 17 digits comes back as the same double as from a GeoPackage.
    const std::string in = dir.path("digits.gpkg");
    write_fixture(in, "GPKG", "digits", 3857, wkbPolygon,
                  {{"POLYGON ((0.12345678901234567 0,1 0,1 1,0 1,0.12345678901234567 0))", {{"id", "1"}}}});
    ASSERT_EQ(run_trisnap(dir, {"snap", in, dir.path("d.csv"), "--tolerance", "1e-9", "-q"}).code, 0);
    ASSERT_EQ(run_trisnap(dir, {"snap", in, dir.path("d.gpkg"), "--tolerance", "1e-9", "-q"}).code, 0);
    EXPECT_EQ(ring_coordinates(dir.path("d.csv")), ring_coordinates(dir.path("d.gpkg")));
}

} // namespace
TEST_F(CliSafety, SignalsStopEveryPhaseWithOneLineAndLeaveNothing)
{
    // SIGINT while snapping ended the run with 130 and no message; SIGTERM while writing said
    // "while writing" in every phase. Now: the phase it stopped in, exit 130 for SIGINT and 1 for
    // SIGTERM, nothing at OUT, nothing temporary.
    const std::string in = data_dir() + "/osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    struct Case {
        const char* phase;
        int signal;
        int code;
        const char* message;
    };
    for (const Case& c : {Case{"snap", SIGINT, 130, "interrupted by SIGINT while snapping; nothing was left at OUT"},
                          Case{"write", SIGTERM, 1, "interrupted by SIGTERM while writing; nothing was left at OUT"}}) {
        SCOPED_TRACE(c.phase);
        const std::string out = dir.path("out.gpkg");
        const std::string start = std::string("\"phase\":\"") + c.phase + "\"";
        // Many small tiles: the snap phase checks for a signal before each.
        const RunOutput r = run_trisnap_killed_when(
            dir, {"snap", in, out, "--tolerance", "0.05", "--tile-vertex-budget", "3000", "--json-progress"},
            [&](const std::string& line) { return line.find(start) != std::string::npos; }, c.signal);
        EXPECT_EQ(r.code, c.code) << r.err;
        EXPECT_NE(r.err.find("trisnap: error: " + std::string(c.message)), std::string::npos) << r.err;
        EXPECT_FALSE(exists(out));
        expect_no_leftovers();
    }
}

} // namespace trisnap::test
