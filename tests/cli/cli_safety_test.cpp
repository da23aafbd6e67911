// Never lose data: the input is never written, OUT and the report appear whole or not at all,
// a full disk is an error (exit 1, nothing at OUT; a work directory's disk is checked before and
// after the read, and named when it fills up), and nothing temporary is left behind.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
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
            if (i > 0) {
                wkt += ',';
            }
            wkt.append(std::to_string(cx + 3 * scale * std::cos(a))).append(" ").append(std::to_string(cy + 3 * scale * std::sin(a)));
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

TEST(CliSupport, OnlyNotWrittenCodesExcuseAMissingFeature)
{
    // Any problem used to excuse a missing feature: a feature that only had repeated points
    // removed (102) could vanish and the accounting tests still passed.
    const nlohmann::json report = nlohmann::json::parse(R"({"problems": [
        {"fid": 1, "code": 102}, {"fid": 2, "code": 201}, {"fid": 3, "code": 105},
        {"fid": 4, "code": 303}, {"fid": 4, "code": 102}, {"fid": 5, "code": 109}, {"fid": 6, "code": 902}]})");
    ReadFeature written;
    written.fid = 6;
    EXPECT_EQ(missing_but_reported(report, {written}), (std::vector<std::int64_t>{2, 4, 5}));
}

TEST_F(CliSafety, ReportNamingTheInputUnderAnyNameIsRefused)
{
    const std::string in = fixture();
    const std::string before = file_bytes(in);
    fs::create_hard_link(in, dir.path("hard.json"));
    fs::create_symlink(in, dir.path("soft.json"));
    for (const std::string& report : {in, dir.path("hard.json"), dir.path("soft.json"), dir.path("./x/../in.gpkg")}) {
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

TEST_F(CliSafety, RenderAndAssessNeverWriteOverTheirInputs)
{
    // `render IN -o pic.svg` with pic.svg a link to IN wrote the picture into IN; `assess --json`
    // the same into SNAPPED. Each output now gets the input protection `snap` has.
    const std::string in = fixture();
    const std::string snapped = dir.path("snapped.gpkg");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, snapped, "--tolerance", "0.01", "-q"}).code, 0);
    const std::string before = file_bytes(in);
    const std::string snapped_before = file_bytes(snapped);
    fs::create_symlink(in, dir.path("soft.svg"));
    fs::create_hard_link(in, dir.path("hard.png"));
    fs::create_symlink(snapped, dir.path("snapped.svg"));
    for (const char* picture : {"soft.svg", "hard.png"}) {
        const RunOutput r = run_trisnap(dir, {"render", in, "-o", dir.path(picture)});
        expect_error(r, 2, "-o " + dir.path(picture) + ": is ");
        EXPECT_NE(r.err.find("a file of the input " + in), std::string::npos) << r.err;
    }
    RunOutput r = run_trisnap(dir, {"render", in, snapped, "-o", dir.path("snapped.svg")});
    expect_error(r, 2, "a file of SNAPPED " + snapped);
    fs::create_symlink(snapped, dir.path("soft.json"));
    r = run_trisnap(dir, {"assess", in, snapped, "--tolerance", "0.01", "--json", dir.path("soft.json")});
    expect_error(r, 2, "--json " + dir.path("soft.json") + ": is ");
    EXPECT_EQ(file_bytes(in), before);
    EXPECT_EQ(file_bytes(snapped), snapped_before);
    // A picture and a JSON file of their own are still written, whole.
    r = run_trisnap(dir, {"render", in, snapped, "-o", dir.path("pic.png")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(file_bytes(dir.path("pic.png")).substr(1, 3), "PNG");
    r = run_trisnap(dir, {"assess", in, snapped, "--tolerance", "0.01", "--json", dir.path("a.json")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(read_json(dir.path("a.json")).is_object());
    expect_no_leftovers();
}

TEST_F(CliSafety, ProblemsLayerOrWorkDirectoryNamingTheInputIsRefused)
{
    // Already refused before render and assess were: kept as a guard for every file snap writes.
    const std::string in = fixture();
    const std::string before = file_bytes(in);
    fs::create_symlink(in, dir.path("soft.gpkg"));
    fs::create_hard_link(in, dir.path("hard.gpkg"));
    for (const char* layer : {"soft.gpkg", "hard.gpkg"}) {
        const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--overwrite",
                                              "--problems-layer", dir.path(layer)});
        expect_error(r, 2, "is a file of the input");
    }
    fs::create_directory_symlink(dir.path(""), dir.path("here"));
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--memory-limit",
                                          "1GiB", "--work-dir", dir.path("here")});
    expect_error(r, 2, "holds files that are not a trisnap run");
    EXPECT_EQ(file_bytes(in), before);
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
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
    // The run stops itself (SIGSTOP) once it has checked its targets, just before the rename;
    // "another process" creates OUT then. It used to be timed by polling for the temporary
    // directory, and skipped when the run was faster than the poll.
    const std::string in = fixture();
    const std::string out = dir.path("out.geojson");
    const ScopedEnv hook("TRISNAP_TEST_RAISE", "before-rename:SIGSTOP");
    const pid_t pid = spawn_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-q"});
    ASSERT_TRUE(wait_until_stopped(pid)) << "the run did not reach its rename";
    EXPECT_FALSE(exists(out));
    std::ofstream(out) << "keep me";
    kill(pid, SIGCONT);
    const RunOutput r = wait_trisnap(dir, pid);
    expect_error(r, 2, "already exists (it appeared while this run was writing)");
    EXPECT_EQ(file_bytes(out), "keep me");
    expect_no_leftovers();
}

/// `n` separate squares (5 vertices each: features small enough for the writer thread).
std::vector<FixtureFeature> many_squares(int n)
{
    std::vector<FixtureFeature> features;
    for (int k = 0; k < n; ++k) {
        const std::string x0 = std::to_string((k % 40) * 10), y0 = std::to_string((k / 40) * 10);
        const std::string x1 = std::to_string((k % 40) * 10 + 6), y1 = std::to_string((k / 40) * 10 + 6);
        features.push_back({"POLYGON ((" + x0 + " " + y0 + "," + x1 + " " + y0 + "," + x1 + " " + y1 + "," + x0 + " " + y1 +
                                "," + x0 + " " + y0 + "))",
                            {{"id", std::to_string(k)}, {"name", "square " + std::to_string(k)}}});
    }
    return features;
}

// The input changes between the read and the write (the run stops itself after the stitch and
// "another process" edits the layer): the write phase reads the layer again for its attributes
// and finds it different. On two threads, with features this small, the stitched features are
// read on a thread of their own (app/handoff.hpp) while the input is read again beside OUT's
// writer: the error stops the writer with that thread still running; on one thread it comes from
// the loop. Either way: one line naming the input, layer and change, exit 1, nothing at OUT.
class CliInputChanged : public ::testing::TestWithParam<int> {
protected:
    TempDir dir;
};

TEST_P(CliInputChanged, DuringTheRunStopsTheWriteAndLeavesNothing)
{
    const std::string threads = std::to_string(GetParam());
    enum class Change { grow, shrink, replace };
    for (const Change change : {Change::grow, Change::shrink, Change::replace}) {
        SCOPED_TRACE(change == Change::grow     ? "a feature added"
                     : change == Change::shrink ? "the last feature deleted"
                                                : "a feature in the middle deleted and one added");
        const std::string in = dir.path(change == Change::grow ? "grow.gpkg" : change == Change::shrink ? "shrink.gpkg" : "replace.gpkg");
        write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon, many_squares(1000));
        const std::string out = dir.path("out.gpkg");
        const ScopedEnv hook("TRISNAP_TEST_RAISE", "stitch:SIGSTOP");
        const pid_t pid = spawn_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--threads", threads, "-q"});
        ASSERT_TRUE(wait_until_stopped(pid)) << "the run did not reach the end of its stitch";
        {
            GDALDatasetUniquePtr ds(GDALDataset::Open(in.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
            ASSERT_TRUE(ds);
            OGRLayer* layer = ds->GetLayer(0);
            if (change != Change::grow) {
                ASSERT_EQ(layer->DeleteFeature(change == Change::shrink ? 1000 : 500), OGRERR_NONE);
            }
            if (change != Change::shrink) {
                OGRFeature f(layer->GetLayerDefn());
                OGRGeometry* g = nullptr;
                OGRGeometryFactory::createFromWkt("POLYGON ((5000 5000,5010 5000,5010 5010,5000 5000))", nullptr, &g);
                f.SetGeometryDirectly(g);
                ASSERT_EQ(layer->CreateFeature(&f), OGRERR_NONE);
            }
        }
        kill(pid, SIGCONT);
        const RunOutput r = wait_trisnap(dir, pid);
        expect_error(r, 1, change == Change::grow     ? "the input changed while trisnap ran (it now has more than 1000 features)"
                           : change == Change::shrink ? "the input changed while trisnap ran (it now ends after 999 features)"
                                                      : "the input changed while trisnap ran (feature 500 has FID 501, was 500)");
        EXPECT_NE(r.err.find(in), std::string::npos) << "the line names the input: " << r.err;
        EXPECT_NE(r.err.find("parcels"), std::string::npos) << "and its layer: " << r.err;
        EXPECT_FALSE(fs::exists(out));
        EXPECT_EQ(leftovers(dir.path("")), std::vector<std::string>{});
    }
}

INSTANTIATE_TEST_SUITE_P(Threads, CliInputChanged, ::testing::Values(1, 2));

// A work file changed between the stitch and the write (the run stops itself after the stitch;
// records.bin is edited): its first entry, a feature the tiles snapped, now says the feature
// passes through, so the stitched features no longer line up with the records. The write phase
// stops with one line saying the work files are damaged, exit 1, nothing at OUT; on two threads
// the stitched features are read on a thread of their own (app/handoff.hpp).
TEST_P(CliInputChanged, WorkFilesOutOfStepWithTheRecordsAreDamaged)
{
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon, many_squares(200));
    const std::string out = dir.path("out.gpkg");
    const std::string work = dir.path("work");
    const ScopedEnv hook("TRISNAP_TEST_RAISE", "stitch:SIGSTOP");
    const pid_t pid = spawn_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--threads", std::to_string(GetParam()),
                                          "--work-dir", work, "-q"});
    ASSERT_TRUE(wait_until_stopped(pid)) << "the run did not reach the end of its stitch";
    {
        // An entry: the FID (8 bytes), the verdict (0 passes through, 1 snapped; bit 7: a
        // problem), the geometry type (4 bytes). app/phases.hpp, RecordEntry.
        std::fstream records(work + "/records.bin", std::ios::in | std::ios::out | std::ios::binary);
        ASSERT_TRUE(records) << "no records.bin in " << work;
        char verdict = 0;
        records.seekg(8);
        records.read(&verdict, 1);
        ASSERT_EQ(verdict & 0x7f, 1) << "the first feature was snapped";
        verdict = static_cast<char>(verdict & 0x80);
        records.seekp(8);
        records.write(&verdict, 1);
        ASSERT_TRUE(records.flush());
    }
    kill(pid, SIGCONT);
    const RunOutput r = wait_trisnap(dir, pid);
    expect_error(r, 1, "damaged work files: the stitched features do not line up with records.bin");
    EXPECT_FALSE(fs::exists(out));
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

// The work directory's disk. Too small for the input: refused before the read spools anything
// (the check after the read would have left the read's work for --resume); too small for what the
// read found: refused after it, the work kept; filling up while spooling (RLIMIT_FSIZE makes
// writes past 64 KiB fail as a full disk does): the same kind of line, naming the work directory.
// A small disk is pretended with TRISNAP_TEST_FREE_DISK (mounting one needs root).
class CliWorkDisk : public ::testing::Test {
protected:
    void SetUp() override
    {
        in = dir.path("many.gpkg");
        write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon, many_polygons(1000));
    }
    void TearDown() override { ::unsetenv("TRISNAP_TEST_FREE_DISK"); }
    std::vector<std::string> args(const std::string& out) const
    {
        return {"snap", in, out, "--tolerance", "0.01", "--work-dir", work, "-q"};
    }
    TempDir dir;
    std::string in;
    std::string work = dir.path("work");
};

TEST_F(CliWorkDisk, TooSmallForTheInputIsRefusedBeforeTheRead)
{
    ::setenv("TRISNAP_TEST_FREE_DISK", "1048576", 1);
    const std::string out = dir.path("out.gpkg");
    RunOutput r = run_trisnap(dir, args(out));
    expect_error(r, 1, work + ": not enough free disk for the work files");
    EXPECT_NE(r.err.find("1 MiB are free"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("--resume"), std::string::npos) << "the read ran: " << r.err;
    EXPECT_FALSE(fs::exists(work)) << "the work directory holds a read that should not have run";
    EXPECT_FALSE(exists(out));
    std::vector<std::string> progress = args(out);
    progress.back() = "--json-progress";
    r = run_trisnap(dir, progress);
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err.find("\"phase\":\"plan\""), std::string::npos) << "the read started: " << r.err;
}

TEST_F(CliWorkDisk, TooSmallForWhatTheReadFoundIsRefusedAfterIt)
{
    // Above the floor from the input's size (features.bin at 0.15 of it, three times, and
    // 64 MiB), below the need after the read (features.bin twice, which for these 24-gons is
    // larger than the GeoPackage, and 64 MiB).
    const auto free = (64ull << 20) + fs::file_size(in);
    ::setenv("TRISNAP_TEST_FREE_DISK", std::to_string(free).c_str(), 1);
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, args(out));
    expect_error(r, 1, work + ": not enough free disk for the work files");
    EXPECT_NE(r.err.find("more are needed for 1000 features"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("kept: add --resume"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
}

TEST_F(CliWorkDisk, FillingUpWhileSpoolingNamesTheWorkDirectory)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap_limited(dir, args(out), Limits{64 * 1024, 0});
    expect_error(r, 1, "work directory " + work + ": no room left for the work files (");
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << "the limit is what failed: " << r.err;
    EXPECT_NE(r.err.find("give --work-dir on a larger disk"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
    EXPECT_EQ(leftovers(dir.path("")), std::vector<std::string>{});
}

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

namespace trisnap::test {
namespace {

// A signal at each moment of the final commit, put there by the test hook TRISNAP_TEST_RAISE
// (the process raises it on itself at the named point): after the writer closed OUT, after the
// report was staged, and once the targets are checked just before the rename. Each used to get
// exit 0 with OUT and the report written: the guard ended with the write phase.
TEST_F(CliSafety, SignalsDuringTheFinalCommitStopTheRunAndLeaveNothing)
{
    const std::string in = fixture();
    struct Case {
        const char* point;
        const char* signal;
        int code;
    };
    for (const Case& c : {Case{"write", "SIGTERM", 1}, Case{"report-staged", "SIGINT", 130},
                          Case{"before-rename", "SIGTERM", 1}}) {
        SCOPED_TRACE(c.point);
        const ScopedEnv hook("TRISNAP_TEST_RAISE", std::string(c.point) + ":" + c.signal);
        const std::string out = dir.path("out.gpkg");
        const std::string report = dir.path("out.json");
        const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
        expect_error(r, c.code, std::string("interrupted by ") + c.signal + " while writing; nothing was left at OUT");
        EXPECT_FALSE(exists(out));
        EXPECT_FALSE(exists(report));
        expect_no_leftovers();
    }
}

TEST_F(CliSafety, SignalJustBeforeTheRenameLeavesAnOverwrittenOutAsItWas)
{
    // A Shapefile OUT with --overwrite: its old files are removed only after the last check.
    const std::string in = fixture();
    const std::string out = dir.path("out.shp");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-q"}).code, 0);
    const std::string before = file_bytes(out) + file_bytes(dir.path("out.dbf"));
    const ScopedEnv hook("TRISNAP_TEST_RAISE", "before-rename:SIGTERM");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.02", "--overwrite"});
    expect_error(r, 1, "interrupted by SIGTERM while writing");
    EXPECT_EQ(file_bytes(out) + file_bytes(dir.path("out.dbf")), before);
    expect_no_leftovers();
}

TEST_F(CliSafety, SignalAfterTheRenameFindsTheRunCompleteAndSaysSo)
{
    // Once OUT and the report are in place the run is complete: exit 0, both whole, one warning.
    // The same once an updated GeoPackage's transaction has committed (nothing takes it back).
    const std::string in = fixture();
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("out.json");
    {
        const ScopedEnv hook("TRISNAP_TEST_RAISE", "after-rename:SIGTERM");
        const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "trisnap: warning: SIGTERM came after the output was in place: the run finished\n");
    }
    EXPECT_EQ(read_layer(out).size(), read_json(report)["counts"]["written"].get<std::size_t>());
    const ScopedEnv hook("TRISNAP_TEST_RAISE", "write:SIGINT");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-nln", "again", "--update"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "trisnap: warning: SIGINT came after the output was in place: the run finished\n");
    EXPECT_FALSE(read_layer(out, "again").empty());
    expect_no_leftovers();
}

TEST_F(CliSafety, SignalsNameThePhaseTheyStopped)
{
    // A signal in the spool phase was reported "while snapping" and one in the seam check
    // "while writing": each was seen only by the next phase's first check.
    const std::string in = fixture();
    const std::string out = dir.path("out.gpkg");
    struct Case {
        const char* point;
        const char* signal;
        int code;
        const char* activity;
    };
    for (const Case& c : {Case{"plan", "SIGTERM", 1, "reading"}, Case{"spool", "SIGTERM", 1, "spooling"},
                          Case{"snap", "SIGINT", 130, "snapping"}, Case{"stitch", "SIGINT", 130, "stitching"}}) {
        SCOPED_TRACE(c.point);
        const ScopedEnv hook("TRISNAP_TEST_RAISE", std::string(c.point) + ":" + c.signal);
        const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01"});
        expect_error(r, c.code, std::string("interrupted by ") + c.signal + " while " + c.activity +
                                    "; nothing was left at OUT");
        EXPECT_FALSE(exists(out));
        expect_no_leftovers();
    }
}

} // namespace
} // namespace trisnap::test
