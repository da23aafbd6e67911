// `trisnap snap` tiled from the command line: identical bytes for --threads 1 and N, for tiled
// and --no-tiles, run to run; the report lists the tiles; tiling options are checked.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>

namespace trisnap::test {
namespace {

const std::string andorra() { return data_dir() + "/snapoly_andorra/andorra.gpkg"; }

TEST(CliTiling, ThreadsTilesAndNoTilesGiveIdenticalBytes)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    const std::vector<std::vector<std::string>> variants{
        {"--no-tiles"}, {"--threads", "1"}, {"--threads", "2"}, {"--tile-size", "0.02", "--threads", "1"},
        {"--tile-size", "0.02", "--threads", "2"}, {"--tile-vertex-budget", "3000", "--threads", "2"}};
    std::string first;
    for (std::size_t k = 0; k < variants.size(); ++k) {
        const std::string out = dir.path("out" + std::to_string(k) + ".gpkg");
        std::vector<std::string> args{"snap", andorra(), out, "--tolerance", "1e-6", "-q", "--report", out + ".json"};
        args.insert(args.end(), variants[k].begin(), variants[k].end());
        const RunOutput r = run_trisnap(dir, args);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        const std::string bytes = file_bytes(out);
        ASSERT_FALSE(bytes.empty());
        if (k == 0) first = bytes;
        else EXPECT_EQ(bytes, first) << "variant " << k << " differs from --no-tiles";
        const auto report = read_json(out + ".json");
        EXPECT_EQ(report["tiling"]["tiled"].get<bool>(), k != 0);
        if (k >= 3) {
            EXPECT_GT(report["tiling"]["tiles"].get<int>(), 1);
            EXPECT_EQ(report["tiling"]["list"].size(), report["tiling"]["tiles"].get<std::size_t>());
            std::size_t owned = 0;
            for (const auto& t : report["tiling"]["list"]) owned += t["owned_edges"].get<std::size_t>();
            EXPECT_GT(owned, 0u);
        }
    }
}

// The read phase's second thread (app/read_phase.cpp; TRISNAP_READ_SPLIT_MIN=1 lets it read a
// layer this small): the output, the report's counts and problems are the one-thread run's, the
// log says which features it read; started one row late (TRISNAP_READ_SPLIT_SKEW, a driver
// whose order disagreed) its features are set aside and the run reads on alone, to the same
// bytes; out of core (--memory-limit 512MiB and more) alike, its part spilled to the work directory. At the
// default minimum (20,000 features) Andorra's 5,757 are read on one thread, and with --no-tiles
// a layer of any size.
TEST(CliTiling, TheSecondReaderGivesTheOneThreadBytes)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    auto run = [&](const std::string& name, const std::vector<std::string>& extra) {
        const std::string out = dir.path(name + ".gpkg");
        std::vector<std::string> args{"snap", andorra(), out, "--tolerance-m", "2", "-v", "--report", out + ".json"};
        args.insert(args.end(), extra.begin(), extra.end());
        const RunOutput r = run_trisnap(dir, args);
        EXPECT_EQ(r.code, 0) << r.err;
        return std::make_tuple(file_bytes(out), read_json(out + ".json"), r.err);
    };
    const auto [one_bytes, one_report, one_log] = run("one", {"--threads", "1"});
    ASSERT_FALSE(one_bytes.empty());
    ASSERT_GT(one_report["problems"].size(), 0u) << "the comparison wants problems to compare";
    const auto [plain_bytes, plain_report, plain_log] = run("plain", {"--threads", "2"});
    EXPECT_EQ(plain_log.find("second thread"), std::string::npos) << plain_log;
    EXPECT_EQ(plain_bytes, one_bytes);
    const auto same_as_one = [&](const std::string& bytes, const nlohmann::json& report) {
        EXPECT_EQ(bytes, one_bytes);
        EXPECT_EQ(report["problems"], one_report["problems"]);
        EXPECT_EQ(report["counts"], one_report["counts"]);
        EXPECT_EQ(report["input"]["features"], one_report["input"]["features"]);
    };
    {
        const ScopedEnv split("TRISNAP_READ_SPLIT_MIN", "1");
        const auto [bytes, report, log] = run("split", {"--threads", "2"});
        EXPECT_NE(log.find("read: features 3456 to 5757 of 5757 read on a second thread"), std::string::npos) << log;
        same_as_one(bytes, report);
        // Out of core the part goes to files of the work directory as it is read, not to memory;
        // under a limit below 512 MiB one thread reads (what the second holds would stay).
        const auto [ooc_bytes, ooc_report, ooc_log] = run("split-ooc", {"--threads", "2", "--memory-limit", "512MiB"});
        EXPECT_NE(ooc_log.find("read: features 3456 to 5757 of 5757 read on a second thread"), std::string::npos) << ooc_log;
        same_as_one(ooc_bytes, ooc_report);
        const auto [tight_bytes, tight_report, tight_log] = run("tight", {"--threads", "2", "--memory-limit", "511MiB"});
        EXPECT_EQ(tight_log.find("second thread"), std::string::npos) << tight_log;
        same_as_one(tight_bytes, tight_report);
        const auto [untiled_bytes, untiled_report, untiled_log] = run("untiled", {"--threads", "2", "--no-tiles"});
        EXPECT_EQ(untiled_log.find("second thread"), std::string::npos) << "--no-tiles reads on one thread: " << untiled_log;
        EXPECT_EQ(untiled_bytes, one_bytes); // the tiled bytes, as ever
        const ScopedEnv skew("TRISNAP_READ_SPLIT_SKEW", "1");
        const auto [late_bytes, late_report, late_log] = run("late", {"--threads", "2"});
        EXPECT_NE(late_log.find("the second thread's features set aside (it began at FID"), std::string::npos) << late_log;
        EXPECT_EQ(late_log.find("read on a second thread"), std::string::npos) << late_log;
        same_as_one(late_bytes, late_report);
        const auto [late_ooc_bytes, late_ooc_report, late_ooc_log] = run("late-ooc", {"--threads", "2", "--memory-limit", "512MiB"});
        EXPECT_NE(late_ooc_log.find("the second thread's features set aside (it began at FID"), std::string::npos) << late_ooc_log;
        same_as_one(late_ooc_bytes, late_ooc_report);
    }
}

// Problem 210 from the command line, on the layer where `trisnap assess` found the loss: Monaco's
// multipolygons at 5 m, buildings 880 and 4005 (their 9.7 m wall merges into one point). Tiled
// (default budget, and small grid tiles cutting the layer) and untiled runs report the same 210s,
// each on the later feature of its pair, naming the earlier.
TEST(CliTiling, ALostSharedBoundaryIsReportedAlikeTiledAndUntiled)
{
    const std::string monaco = data_dir() + "/osm_monaco_osrm_2020/monaco_osrm_2020.gpkg";
    if (!exists(monaco)) GTEST_SKIP() << "data set absent: " << monaco;
    TempDir dir;
    const std::vector<std::vector<std::string>> variants{{"--no-tiles"}, {}, {"--tile-size", "0.005", "--threads", "2"}};
    std::set<std::pair<std::int64_t, std::string>> first;
    for (std::size_t k = 0; k < variants.size(); ++k) {
        const std::string out = dir.path("out" + std::to_string(k) + ".gpkg");
        std::vector<std::string> args{"snap", monaco, out, "--layer", "multipolygons", "--tolerance-m", "5", "-q",
                                      "--allow-collapse", "--report", out + ".json"};
        args.insert(args.end(), variants[k].begin(), variants[k].end());
        const RunOutput r = run_trisnap(dir, args);
        ASSERT_EQ(r.code, 0) << r.err;
        const auto report = read_json(out + ".json");
        std::set<std::pair<std::int64_t, std::string>> lost;
        for (const auto& p : report["problems"]) {
            if (p["code"] == 210) {
                lost.emplace(p["fid"].get<std::int64_t>(), p["message"].get<std::string>());
            }
        }
        const auto wall = std::find_if(lost.begin(), lost.end(), [](const auto& p) { return p.first == 4005; });
        ASSERT_NE(wall, lost.end()) << "variant " << k;
        EXPECT_EQ(wall->second.rfind("no longer shares a boundary with FID 880:", 0), 0u) << wall->second;
        EXPECT_EQ(lost.size(), 54u) << "variant " << k;
        if (k == 0) first = lost;
        else EXPECT_EQ(lost, first) << "variant " << k << " reports other 210s than --no-tiles";
        if (k == 2) {
            EXPECT_GT(report["tiling"]["tiles"].get<int>(), 4);
        }
    }
}

// The report times each phase's CPU (every thread's) beside its wall time: a phase's own share,
// not the process's total so far, and never more than its two threads can spend.
TEST(CliTiling, ReportGivesEachPhasesCpu)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", andorra(), out, "--tolerance", "1e-6", "--tile-size", "0.01", "-q",
                                          "--threads", "2", "--report", out + ".json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto timings = read_json(out + ".json")["timings_s"];
    const auto& wall = timings["phases"];
    const auto& cpu = timings["cpu_phases"];
    ASSERT_EQ(cpu.size(), wall.size()) << timings;
    ASSERT_EQ(cpu.size(), 5u) << timings;
    double sum = 0;
    for (const auto& [name, seconds] : wall.items()) {
        ASSERT_TRUE(cpu.contains(name)) << name;
        const double c = cpu[name].get<double>();
        EXPECT_GE(c, 0.0) << name;
        // Two threads at most (the tiles' arena, the second reader, the writer thread), with
        // the kernel's accounting granularity.
        EXPECT_LE(c, 2 * seconds.get<double>() + 0.02) << name << ": " << timings;
        sum += c;
    }
    EXPECT_GT(cpu["snap"].get<double>(), 0.5 * wall["snap"].get<double>()) << timings;
    const double process = timings["cpu_process"].get<double>();
    EXPECT_LE(sum, process + 1e-9) << timings;
    EXPECT_GT(process, cpu["snap"].get<double>()) << timings;
}

// The stitch phase reports tiles checked of the tiles there are, in --json-progress as on the bar:
// a total from its start (the report's tiles when no seam merged any), an ETA once some are done,
// and every tile done at the end.
TEST(CliTiling, StitchProgressCountsTheTiles)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", andorra(), out, "--tolerance", "1e-6", "--tile-size", "0.01", "-q",
                                          "--json-progress", "--report", out + ".json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto report = read_json(out + ".json");
    const auto tiles = report["tiling"]["tiles"].get<std::int64_t>();
    ASSERT_GT(tiles, 4);
    std::vector<nlohmann::json> lines;
    for (const std::string& line : r.err_lines()) {
        const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        ASSERT_FALSE(j.is_discarded()) << "not JSON: " << line;
        if (j["phase"] == "stitch") {
            lines.push_back(j);
        }
    }
    ASSERT_GE(lines.size(), 2u) << "no start and end line for the stitch";
    std::int64_t last = 0;
    for (const nlohmann::json& j : lines) {
        EXPECT_EQ(j["unit"], "tiles") << j;
        const auto done = j["done"].get<std::int64_t>();
        const auto total = j["total"].get<std::int64_t>();
        EXPECT_GE(total, tiles) << j;
        EXPECT_GE(done, last) << j;
        EXPECT_LE(done, total) << j;
        if (done > 0 && !j["finished"].get<bool>()) {
            EXPECT_FALSE(j["eta_s"].is_null()) << "no ETA with tiles done: " << j;
        }
        last = done;
    }
    EXPECT_EQ(lines.front()["done"], 0);
    if (report["tiling"]["seam_merges"].get<int>() == 0) {
        EXPECT_EQ(lines.front()["total"].get<std::int64_t>(), tiles);
    }
    EXPECT_TRUE(lines.back()["finished"].get<bool>());
    EXPECT_EQ(lines.back()["done"], lines.back()["total"]);
}

TEST(CliTiling, BadTilingOptionsNameTheOption)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--tile-size", "5", "--no-tiles"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--tile-size or --no-tiles"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--halo", "1"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("tiling.halo"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--tile-size", "1e-9"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--tile-size"), std::string::npos) << r.err;
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
}

TEST(CliTiling, TilingConfigKeysAreReadAndChecked)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    const std::string cfg = dir.path("c.toml");
    {
        std::ofstream f(cfg);
        f << "[tiling]\nsize = 5.0\nhalo = 16.0\n";
    }
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--config", cfg, "--print-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("size = 5.0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("halo = 16.0"), std::string::npos) << r.out;
    {
        std::ofstream f(cfg);
        f << "[tiling]\nsise = 5.0\n";
    }
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--config", cfg});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("tiling.sise"), std::string::npos) << r.err;
}

// --no-tiles in memory keeps only outlines of its spool while the engine runs (stitch/spool.hpp,
// cut_spool_to_outlines): a failure of its one tile still names the same features, in the same
// words, as the same run out of core (which keeps the spool whole).
TEST(CliNoTilesFailure, TheStopLineNamesTheSameFeaturesInMemoryAndOutOfCore)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    ::setenv("TRISNAP_FAIL_TILES", "0", 1);
    auto tile_part = [](const std::string& line) {
        const std::size_t from = line.find("tile 0 (core ");
        const std::size_t to = line.find(") failed: ");
        return from == std::string::npos || to == std::string::npos ? std::string() : line.substr(from, to - from);
    };
    std::vector<std::string> parts;
    for (const bool out_of_core : {false, true}) {
        SCOPED_TRACE(out_of_core ? "out of core" : "in memory");
        const std::string out = dir.path(out_of_core ? "disk.gpkg" : "memory.gpkg");
        std::vector<std::string> args{"snap", andorra(), out, "--no-tiles", "--tolerance", "1e-6", "--threads", "1"};
        if (out_of_core) {
            args.insert(args.end(), {"--memory-limit", "4GiB", "--work-dir", dir.path("work")});
        }
        const RunOutput r = run_trisnap(dir, args);
        EXPECT_EQ(r.code, 1) << r.err;
        ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
        EXPECT_NE(r.err.find("injected failure"), std::string::npos) << r.err;
        EXPECT_FALSE(exists(out));
        parts.push_back(tile_part(r.err));
        EXPECT_NE(parts.back().find(" features: FIDs "), std::string::npos) << r.err;
        EXPECT_NE(parts.back().find(" more"), std::string::npos) << r.err;
    }
    ::unsetenv("TRISNAP_FAIL_TILES");
    EXPECT_EQ(parts[0], parts[1]);
}

// A tile whose engine fails (injected with TRISNAP_FAIL_TILES, stitch/tile_run.cpp): by default
// the run stops with one line naming the tile and leaves nothing; with --on-error skip the tile
// is retried merged with its neighbours, and what fails again is reported feature by feature
// (303) while everything else is written exactly as without the failure.
class CliOnError : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
        const RunOutput r = run_trisnap(dir, with_options({"snap", andorra(), plain, "-q", "--report", plain + ".json"}));
        ASSERT_EQ(r.code, 0) << r.err;
        const auto report = read_json(plain + ".json");
        std::size_t most = 0;
        for (const auto& t : report["tiling"]["list"]) {
            if (t["features"].get<std::size_t>() > most) {
                most = t["features"].get<std::size_t>();
                tile = t["id"].get<std::size_t>();
            }
        }
        ASSERT_GT(report["tiling"]["tiles"].get<std::size_t>(), 4u);
    }
    void TearDown() override { ::unsetenv("TRISNAP_FAIL_TILES"); }
    static std::vector<std::string> with_options(std::vector<std::string> args)
    {
        for (const char* a : {"--tolerance", "1e-6", "--tile-size", "0.02", "--threads", "2"}) args.push_back(a);
        return args;
    }
    TempDir dir;
    const std::string plain = dir.path("plain.gpkg");
    std::size_t tile = 0;
};

TEST_F(CliOnError, DefaultStopsWithOneLineNamingTheTileAndLeavesNothing)
{
    ::setenv("TRISNAP_FAIL_TILES", std::to_string(tile).c_str(), 1);
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, with_options({"snap", andorra(), out}));
    EXPECT_EQ(r.code, 1);
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("tile " + std::to_string(tile) + " (core "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(" features: FIDs "), std::string::npos) << "the line names the tile's features" << r.err;
    EXPECT_NE(r.err.find("injected failure"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--on-error skip"), std::string::npos) << r.err;
    EXPECT_FALSE(exists(out));
}

TEST_F(CliOnError, SkipReportsEveryDroppedFeatureAndWritesTheRestUnchanged)
{
    ::setenv("TRISNAP_FAIL_TILES", std::to_string(tile).c_str(), 1);
    const std::string out = dir.path("out.gpkg");
    RunOutput r = run_trisnap(dir, with_options({"snap", andorra(), out, "--on-error", "skip", "--report", out + ".json"}));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(" of them in failed tiles"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("303 tile_failed x"), std::string::npos) << r.out;
    const auto report = read_json(out + ".json");
    EXPECT_EQ(report["tiling"]["tiles_failed"].get<std::size_t>(), 1u);
    const std::size_t failed = report["tiling"]["failed_features"].get<std::size_t>();
    ASSERT_GT(failed, 0u);
    std::set<std::int64_t> dropped;
    for (const auto& p : report["problems"]) {
        if (p["code"].get<int>() == 303) {
            EXPECT_TRUE(dropped.insert(p["fid"].get<std::int64_t>()).second);
            const std::string message = p["message"].get<std::string>();
            EXPECT_NE(message.find("tile " + std::to_string(tile) + " ("), std::string::npos) << message;
            EXPECT_NE(message.find(" features: FIDs "), std::string::npos) << message;
            EXPECT_NE(message.find("failed alone and merged with its neighbours (injected failure"), std::string::npos)
                << message;
            EXPECT_NE(message.find("and untiled in its region (injected failure"), std::string::npos) << message;
        }
    }
    EXPECT_EQ(dropped.size(), failed);
    std::map<std::int64_t, std::string> expected;
    for (const ReadFeature& f : read_layer(plain)) expected[f.fid] = f.wkt;
    std::size_t written = 0;
    for (const ReadFeature& f : read_layer(out)) {
        EXPECT_FALSE(dropped.count(f.fid)) << "FID " << f.fid << " has 303 but was written";
        EXPECT_EQ(f.wkt, expected.at(f.fid)) << "FID " << f.fid;
        ++written;
    }
    EXPECT_EQ(written + dropped.size(), expected.size());
    EXPECT_EQ(report["counts"]["written"].get<std::size_t>(), written);
    // A tile that fails only alone goes through merged with its neighbours: nothing is lost.
    ::setenv("TRISNAP_FAIL_TILES", (std::to_string(tile) + "/1").c_str(), 1);
    const std::string retried = dir.path("retried.gpkg");
    r = run_trisnap(dir, with_options({"snap", andorra(), retried, "-q", "--on-error", "skip"}));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(file_bytes(retried), file_bytes(plain));
    // The config key does the same; a bad value names the key.
    const std::string cfg = dir.path("c.toml");
    std::ofstream(cfg) << "[run]\non_error = \"skip\"\n";
    ::setenv("TRISNAP_FAIL_TILES", std::to_string(tile).c_str(), 1);
    r = run_trisnap(dir, with_options({"snap", andorra(), dir.path("cfg.gpkg"), "-q", "--settings", cfg}));
    EXPECT_EQ(r.code, 0) << r.err;
    std::ofstream(cfg) << "[run]\non_error = \"ignore\"\n";
    r = run_trisnap(dir, with_options({"snap", andorra(), dir.path("bad.gpkg"), "--settings", cfg}));
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("on_error"), std::string::npos) << r.err;
    r = run_trisnap(dir, with_options({"snap", andorra(), dir.path("bad.gpkg"), "--on-error", "ignore"}));
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--on-error"), std::string::npos) << r.err;
}

TEST_F(CliOnError, SkipRetriesTheTileUntiledInItsRegionBeforeDroppingAnything)
{
    // A tile that fails whenever its features are cut, alone and merged with its neighbours,
    // used to lose its features (303). Its last try snaps its region with every feature given
    // whole, as an untiled run sees it: nothing is lost, and the output is the run's without a
    // failure.
    ::setenv("TRISNAP_FAIL_TILES", (std::to_string(tile) + "/cut").c_str(), 1);
    const std::string out = dir.path("whole.gpkg");
    RunOutput r = run_trisnap(dir, with_options({"snap", andorra(), out}));
    ASSERT_EQ(r.code, 1) << "the tile fails as it is cut: " << r.err;
    r = run_trisnap(dir, with_options({"snap", andorra(), out, "-q", "--on-error", "skip", "--report", out + ".json"}));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto report = read_json(out + ".json");
    EXPECT_EQ(report["tiling"]["tiles_failed"].get<std::size_t>(), 0u);
    EXPECT_EQ(report["tiling"]["failed_features"].get<std::size_t>(), 0u);
    EXPECT_FALSE(report["problems_by_code"].contains("303")) << report["problems_by_code"].dump();
    // The tile went through on its own (split back from the merged try that failed), not merged.
    bool found = false;
    for (const auto& t : report["tiling"]["list"]) {
        if (t["id"].get<std::size_t>() == tile) {
            found = true;
            EXPECT_EQ(t["leaves"].get<std::size_t>(), 1u) << t.dump();
        }
    }
    EXPECT_TRUE(found) << "tile " << tile << " is not in the report's list";
    EXPECT_EQ(file_bytes(out), file_bytes(plain));
}

} // namespace
} // namespace trisnap
