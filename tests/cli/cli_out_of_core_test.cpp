// Out of core from the command line (label slow): a replicated real layer of 218k polygons
// under --memory-limit 256MiB keeps the process's peak under the limit and writes the bytes of
// the in-memory run; a run killed (SIGKILL) in three different phases and continued with
// --resume writes the same bytes; a limit too small for one feature is a clear error that
// leaves nothing at OUT, and the smallest limit it suggests runs through; work directories of
// other runs are refused; 100 k problems under a limit give the in-memory report.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace trisnap::test {
namespace {

namespace fs = std::filesystem;

const std::string jakarta() { return data_dir() + "/osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg"; }

// Four copies of Jakarta's buildings side by side (218k polygons), made once per test binary.
const std::string& replicated()
{
    static const std::string path = [] {
        const std::string p = (fs::temp_directory_path() / ("trisnap-ooc-" + std::to_string(::getpid()) + ".gpkg")).string();
        const std::string command = std::string("'") + TRISNAP_MAKE_LARGE_LAYER_EXE + "' '" + jakarta() + "' '" + p +
                                    "' --polygons 217728 --layer building >/dev/null";
        return std::system(command.c_str()) == 0 ? p : std::string();
    }();
    return path;
}

class OutOfCore : public ::testing::Test {
protected:
    static void TearDownTestSuite()
    {
        std::error_code ec;
        fs::remove(replicated(), ec);
    }
    void SetUp() override
    {
        if (!exists(jakarta())) {
            GTEST_SKIP() << "data set absent: " << jakarta();
        }
        ASSERT_FALSE(replicated().empty()) << "bench_make_large_layer failed";
    }
    /// The in-memory run's bytes (once).
    const std::string& reference()
    {
        static std::string bytes;
        if (bytes.empty()) {
            const std::string out = m_dir.path("reference.gpkg");
            const RunOutput r = run_trisnap(m_dir, {"snap", replicated(), out, "--tolerance", "0.1", "-q"});
            EXPECT_EQ(r.code, 0) << r.err;
            bytes = file_bytes(out);
        }
        return bytes;
    }
    std::vector<std::string> ooc_args(const std::string& out) const
    {
        return {"snap", replicated(), out, "--tolerance", "0.1", "--memory-limit", "256MiB", "--threads", "2", "-q"};
    }
    TempDir m_dir;
};

TEST_F(OutOfCore, PeakStaysUnderTheLimitAndBytesEqualTheInMemoryRun)
{
    const std::string out = m_dir.path("ooc.gpkg");
    std::vector<std::string> args = ooc_args(out);
    args.insert(args.end(), {"--report", out + ".json"});
    const RunOutput r = run_trisnap(m_dir, args);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json report = read_json(out + ".json");
    EXPECT_EQ(report["memory"]["mode"], "out_of_core");
    EXPECT_LE(report["peak_memory_mb"].get<double>(), 256.0) << "peak RSS over --memory-limit 256MiB";
    EXPECT_GT(report["tiling"]["tiles"].get<int>(), 4) << "the limit must have made several tiles";
    EXPECT_GT(report["memory"]["spool_bytes"].get<double>(), 0);
    EXPECT_FALSE(fs::exists(m_dir.path(".ooc.gpkg.trisnap-work"))) << "work directory left after success";
    EXPECT_EQ(report["counts"]["written"].get<int>(), 217728);
    EXPECT_TRUE(file_bytes(out) == reference()) << "out-of-core bytes differ from the in-memory run";
}

// Above the spatial index's box budget (a thirty-second of the limit: 349,525 boxes under
// 256MiB) the writer sorts the boxes in runs on disk and packs the same tree: eight copies of
// Jakarta's buildings (435,456 polygons) out of core give the in-memory run's bytes (GDAL used
// to build such an index itself, in another layout and ~6 us a feature), within the limit, and
// leave nothing but OUT beside it.
TEST(OutOfCoreIndex, AboveTheBoxBudgetTheIndexIsSortedOnDiskAndTheBytesStayTheSame)
{
    if (!exists(jakarta())) {
        GTEST_SKIP() << "data set absent: " << jakarta();
    }
    TempDir dir;
    const std::string layer = dir.path("eight.gpkg");
    const std::string command = std::string("'") + TRISNAP_MAKE_LARGE_LAYER_EXE + "' '" + jakarta() + "' '" + layer +
                                "' --polygons 435456 --layer building >/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    fs::create_directory(dir.path("memory"));
    fs::create_directory(dir.path("limited"));
    const std::string memory = dir.path("memory/out.gpkg");
    const std::string limited = dir.path("limited/out.gpkg");
    const RunOutput a = run_trisnap(dir, {"snap", layer, memory, "--tolerance", "0.1", "-q"});
    ASSERT_EQ(a.code, 0) << a.err;
    const RunOutput b = run_trisnap(dir, {"snap", layer, limited, "--tolerance", "0.1", "--memory-limit", "256MiB", "--threads", "2",
                                          "-q", "--report", dir.path("limited.json")});
    ASSERT_EQ(b.code, 0) << b.err;
    const nlohmann::json report = read_json(dir.path("limited.json"));
    EXPECT_EQ(report["counts"]["written"].get<int>(), 435456);
    EXPECT_GT(report["counts"]["written"].get<double>(), 256.0 * 1024 * 1024 / 32 / 24) << "the boxes must exceed the budget";
    EXPECT_LE(report["peak_memory_mb"].get<double>(), 256.0);
    EXPECT_TRUE(file_bytes(limited) == file_bytes(memory)) << "the index sorted on disk changed the bytes";
    std::vector<std::string> left;
    for (const auto& entry : fs::recursive_directory_iterator(dir.path("limited"))) {
        left.push_back(entry.path().filename().string());
    }
    EXPECT_EQ(left, std::vector<std::string>{"out.gpkg"}) << "scratch or work files left beside OUT";
}

// Killed at the start of the spool phase (the layer is spooled), during the snap phase (some
// tiles done), at the start of the write phase (every tile done): --resume finishes each.
TEST_F(OutOfCore, KilledInThreePhasesAndResumedGivesTheSameBytes)
{
    struct Kill {
        const char* phase;
        bool after_some_work;
    };
    for (const Kill k : {Kill{"spool", false}, Kill{"snap", true}, Kill{"write", false}}) {
        SCOPED_TRACE(k.phase);
        const std::string out = m_dir.path(std::string("killed_") + k.phase + ".gpkg");
        std::vector<std::string> args = ooc_args(out);
        args.push_back("--json-progress");
        const RunOutput killed = run_trisnap_killed_when(m_dir, args, [&](const std::string& line) {
            const auto j = nlohmann::json::parse(line, nullptr, false);
            return !j.is_discarded() && j.value("phase", "") == k.phase && (!k.after_some_work || j.value("done", 0) > 0);
        });
        ASSERT_EQ(killed.code, 137) << "not killed: " << killed.err;
        EXPECT_FALSE(fs::exists(out)) << "a killed run left OUT";
        const std::string work = m_dir.path(".killed_" + std::string(k.phase) + ".gpkg.trisnap-work");
        ASSERT_TRUE(fs::exists(work)) << "no work directory to resume";
        // Without --resume the work directory is refused, never silently reused or removed.
        RunOutput again = run_trisnap(m_dir, ooc_args(out));
        EXPECT_EQ(again.code, 2) << again.err;
        EXPECT_NE(again.err.find("--resume"), std::string::npos) << again.err;
        std::vector<std::string> resume = ooc_args(out);
        resume.insert(resume.end(), {"--resume", "--report", out + ".json"});
        const RunOutput resumed = run_trisnap(m_dir, resume);
        ASSERT_EQ(resumed.code, 0) << resumed.err;
        EXPECT_TRUE(read_json(out + ".json")["memory"]["resumed"].get<bool>());
        EXPECT_TRUE(file_bytes(out) == reference()) << "resumed bytes differ from an uninterrupted run";
        EXPECT_FALSE(fs::exists(work));
    }
}

// A ring of 120k vertices within 10 t of its centre: no tile can be smaller than its halo, so a
// budget smaller than that one ring is refused before anything is written (the work directory,
// holding the read layer, is kept for --resume with a larger limit).
TEST_F(OutOfCore, LimitTooSmallForOneFeatureIsAClearErrorAndLeavesNothing)
{
    std::string wkt = "POLYGON((";
    const int n = 120000;
    char point[64];
    for (int i = 0; i <= n; ++i) {
        const double a = 2 * M_PI * (i % n) / n;
        std::snprintf(point, sizeof point, "%s%.17g %.17g", i ? "," : "", 10 * std::cos(a), 10 * std::sin(a));
        wkt += point;
    }
    wkt += "))";
    const std::string in = m_dir.path("dense.gpkg");
    write_fixture(in, "GPKG", "dense", 3857, wkbPolygon, {FixtureFeature{wkt, {{"id", "1"}}}});
    const std::string out = m_dir.path("dense_out.gpkg");
    const RunOutput r = run_trisnap(m_dir, {"snap", in, out, "--tolerance", "1", "--memory-limit", "160MiB"});
    expect_error(r, 2, "--memory-limit 160 MiB is too small");
    EXPECT_NE(r.err.find("id 1"), std::string::npos) << "the feature is not named: " << r.err;
    EXPECT_NE(r.err.find("smallest limit that would work is about"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("kept: add --resume to continue it"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(fs::exists(m_dir.path(".dense_out.gpkg.trisnap-work"))) << "the read phase's work is kept for --resume";
    // The limit it suggests is enough for a fresh run: it plans and spools (where a limit is
    // refused) and starts snapping, where it is stopped (snapping this ring takes minutes).
    const std::string marker = "the smallest limit that would work is about ";
    const long long mib = std::stoll(r.err.substr(r.err.find(marker) + marker.size()));
    const RunOutput fresh = run_trisnap_killed_when(
        m_dir, {"snap", in, m_dir.path("dense_fresh.gpkg"), "--tolerance", "1", "--memory-limit", std::to_string(mib) + "MiB",
                "--json-progress"},
        [](const std::string& line) { return line.find("\"phase\":\"snap\"") != std::string::npos; });
    EXPECT_EQ(fresh.code, 137) << "a fresh run at the suggested " << mib << " MiB did not reach the snap phase: " << fresh.err;
}

TEST_F(OutOfCore, WorkDirectoriesOfOtherRunsAreRefused)
{
    const std::string work = m_dir.path("work");
    const std::string out = m_dir.path("w.gpkg");
    const std::string in = write_snapping_gpkg(m_dir, "in.gpkg");
    fs::create_directory(work);
    std::ofstream(work + "/notes.txt") << "mine";
    RunOutput r = run_trisnap(m_dir, {"snap", in, out, "--tolerance", "0.01", "--work-dir", work});
    expect_error(r, 2, "holds files that are not a trisnap run");
    EXPECT_TRUE(fs::exists(work + "/notes.txt")) << "the user's file was touched";
    // A run killed after its read phase, then continued with another tolerance: refused.
    const std::string work2 = m_dir.path("work2");
    r = run_trisnap_killed_when(m_dir, {"snap", replicated(), out, "--tolerance", "0.1", "--work-dir", work2, "--json-progress"},
                                [](const std::string& line) { return line.find("\"phase\":\"spool\"") != std::string::npos; });
    ASSERT_EQ(r.code, 137);
    r = run_trisnap(m_dir, {"snap", replicated(), out, "--tolerance", "0.2", "--work-dir", work2, "--resume"});
    expect_error(r, 2, "holds a run of another command or input (differs in snap.tolerance)");
    r = run_trisnap(m_dir, {"snap", in, out, "--tolerance", "0.1", "--work-dir", work2, "--resume"});
    expect_error(r, 2, "differs in input");
    EXPECT_FALSE(fs::exists(out));
}

// "The smallest limit that would work" is the limit a fresh run needs, not the one that would
// have been enough with the margin of the limit tried (the margin grows with the limit): the
// same command with the suggested limit runs through, and one with three quarters of it is
// refused again.
// Andorra at t = 1e-6 on two threads under a limit ("": none), into `name` in a directory of its own.
class OutOfCoreLimits : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (!exists(m_andorra)) {
            GTEST_SKIP() << "data set absent: " << m_andorra;
        }
    }
    RunOutput run_at(const std::string& limit, const std::string& name, std::vector<std::string> extra = {"-q"})
    {
        std::vector<std::string> args{"snap", m_andorra, dir.path(name), "--tolerance", "1e-6", "--threads", "2"};
        if (!limit.empty()) {
            args.insert(args.end(), {"--memory-limit", limit});
        }
        args.insert(args.end(), extra.begin(), extra.end());
        return run_trisnap(dir, args);
    }
    const std::string m_andorra = data_dir() + "/snapoly_andorra/andorra.gpkg";
    TempDir dir;
};

TEST_F(OutOfCoreLimits, TheSuggestedLimitIsEnoughForAFreshRun)
{
    const RunOutput small = run_at("32MiB", "small.gpkg");
    expect_error(small, 2, "--memory-limit 32 MiB is too small");
    const std::string marker = "the smallest limit that would work is about ";
    const std::size_t at = small.err.find(marker);
    ASSERT_NE(at, std::string::npos) << small.err;
    const long long mib = std::stoll(small.err.substr(at + marker.size()));
    EXPECT_NE(small.err.find(std::to_string(mib) + " MiB", at), std::string::npos) << small.err;
    ASSERT_GT(mib, 32);
    const RunOutput suggested = run_at(std::to_string(mib) + "MiB", "suggested.gpkg");
    EXPECT_EQ(suggested.code, 0) << "a fresh run at the suggested " << mib << " MiB failed: " << suggested.err;
    EXPECT_TRUE(exists(dir.path("suggested.gpkg")));
    const RunOutput less = run_at(std::to_string(mib * 3 / 4) + "MiB", "less.gpkg");
    EXPECT_EQ(less.code, 2) << "three quarters of the suggestion ran too: it is not the smallest";
}

// A limit that leaves the tiles less than --tile-vertex-budget says so once, after the tiles,
// with the budget the plan used: every tile holds at most that many vertices, and the output is
// the one of a run without a limit. A limit with room for full-size tiles says nothing.
TEST_F(OutOfCoreLimits, SmallerTilesUnderALimitAreSaidWithTheBudgetThePlanUsed)
{
    const RunOutput free_run = run_at("", "free.gpkg");
    ASSERT_EQ(free_run.code, 0) << free_run.err;
    const RunOutput tight = run_at("170MiB", "tight.gpkg", {"--report", dir.path("tight.gpkg.json")});
    ASSERT_EQ(tight.code, 0) << tight.err;
    const std::string marker = "tiles of at most ";
    std::size_t said = 0;
    std::uint64_t budget = 0;
    for (const std::string& line : tight.err_lines()) {
        if (const std::size_t at = line.find(marker); at != std::string::npos) {
            ++said;
            budget = std::stoull(line.substr(at + marker.size()));
            EXPECT_NE(line.find("instead of 50000 (--tile-vertex-budget)"), std::string::npos) << line;
            EXPECT_NE(line.find("would give full-size tiles"), std::string::npos) << line;
        }
    }
    ASSERT_EQ(said, 1u) << "the smaller tiles are said once: " << tight.err;
    ASSERT_GT(budget, 0u);
    ASSERT_LT(budget, 50000u);
    const nlohmann::json report = read_json(dir.path("tight.gpkg.json"));
    ASSERT_GT(report["tiling"]["list"].size(), 1u);
    for (const nlohmann::json& tile : report["tiling"]["list"]) {
        EXPECT_LE(tile["input_vertices"].get<std::uint64_t>(), budget) << "tile " << tile["id"] << " over the budget said";
    }
    EXPECT_EQ(report["counts"]["written"].get<int>(), 5757);
    EXPECT_TRUE(file_bytes(dir.path("tight.gpkg")) == file_bytes(dir.path("free.gpkg"))) << "smaller tiles changed the bytes";
    const RunOutput roomy = run_at("2GiB", "roomy.gpkg", {});
    ASSERT_EQ(roomy.code, 0) << roomy.err;
    EXPECT_EQ(roomy.err.find(marker), std::string::npos) << roomy.err;
}

// A layer whose every feature has a problem (a repeated vertex: 102), 100 k of them: under a
// limit they go to sorted runs in the work directory and come back one at a time, so the report's
// problem list and the problems layer are those of the in-memory run, byte for byte.
TEST(OutOfCoreProblems, ManyProblemsUnderALimitGiveTheInMemoryReportAndLayer)
{
    TempDir dir;
    std::vector<FixtureFeature> features;
    const int n = 100000;
    for (int k = 0; k < n; ++k) {
        const int x = (k % 320) * 3;
        const int y = (k / 320) * 3;
        char wkt[160];
        std::snprintf(wkt, sizeof wkt, "POLYGON((%d %d,%d %d,%d %d,%d %d,%d %d,%d %d))", x, y, x + 1, y, x + 1, y, x + 1,
                      y + 1, x, y + 1, x, y);
        features.push_back({wkt, {{"id", std::to_string(k)}}});
    }
    const std::string in = dir.path("repeated.gpkg");
    write_fixture(in, "GPKG", "squares", 3857, wkbPolygon, features);
    auto run = [&](const std::string& name, std::vector<std::string> extra) {
        std::vector<std::string> args{"snap", in, dir.path(name + ".gpkg"), "--tolerance", "0.01", "--report",
                                      dir.path(name + ".json"), "--problems-layer", dir.path(name + ".geojson")};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_trisnap(dir, args);
    };
    const RunOutput memory = run("memory", {"-q"});
    ASSERT_EQ(memory.code, 0) << memory.err;
    const RunOutput limited = run("limited", {"--memory-limit", "256MiB", "-v"}); // 8 MiB of problems at once
    ASSERT_EQ(limited.code, 0) << limited.err;
    const std::string marker = "problems: " + std::to_string(n) + ", in ";
    const std::size_t at = limited.err.find(marker);
    ASSERT_NE(at, std::string::npos) << limited.err;
    EXPECT_GE(std::stoi(limited.err.substr(at + marker.size())), 2) << "the problems did not go to the work directory";
    const nlohmann::json a = read_json(dir.path("memory.json"));
    const nlohmann::json b = read_json(dir.path("limited.json"));
    EXPECT_EQ(b["memory"]["mode"], "out_of_core");
    ASSERT_EQ(a["problems"].size(), static_cast<std::size_t>(n));
    EXPECT_EQ(a["problems_by_code"], b["problems_by_code"]);
    EXPECT_EQ(a["counts"], b["counts"]);
    // The problem list as text, from "problems_by_code" to the end: the same bytes.
    auto tail = [](const std::string& text) { return text.substr(text.rfind("\"problems_by_code\"")); };
    EXPECT_TRUE(tail(file_bytes(dir.path("memory.json"))) == tail(file_bytes(dir.path("limited.json"))));
    EXPECT_TRUE(file_bytes(dir.path("memory.geojson")) == file_bytes(dir.path("limited.geojson")));
}

TEST(OutOfCoreOptions, MemoryLimitIsReadFromTheConfigAndChecked)
{
    TempDir dir;
    const std::string in = write_snapping_gpkg(dir, "in.gpkg");
    const std::string cfg = dir.path("c.toml");
    std::ofstream(cfg) << "[run]\nmemory_limit = \"300MiB\"\n";
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--settings", cfg, "--print-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("memory_limit = 314572800"), std::string::npos) << r.out;
    std::ofstream(cfg) << "[run]\nmemory_limit = \"lots\"\n";
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--settings", cfg});
    expect_error(r, 2, "c.toml:2: key 'run.memory_limit'");
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--memory-limit", "12 parsecs"});
    expect_error(r, 2, "--memory-limit '12 parsecs'");
}

} // namespace
} // namespace trisnap::test
