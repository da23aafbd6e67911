// A snap split across processes as a cluster runs it: `trisnap plan`, N `trisnap snap-tiles`
// processes in parallel, each told its shard only by an array-task variable (as Slurm, a
// Kubernetes Indexed Job or AWS Batch set them), then `trisnap stitch`. The output must have the
// bytes of `trisnap snap` with the same options on one machine; a killed task run again changes
// nothing (and the temporary files it left on this host are removed); a stitch with a shard
// missing names the tiles and shards; a run directory made by another version or build, or for
// another input, is refused.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <set>
#include <sstream>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace trisnap::test {
namespace {
namespace fs = std::filesystem;

const std::string andorra() { return data_dir() + "/snapoly_andorra/andorra.gpkg"; }
const std::string monaco_pbf() { return data_dir() + "/osm_monaco_osrm_2020/monaco.osm.pbf"; }

/// The environment without any array-task variable, plus `extra` ("NAME=value").
std::vector<std::string> task_environment(const std::vector<std::string>& extra)
{
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
        const std::string item(*e);
        const bool task = item.rfind("SLURM_", 0) == 0 || item.rfind("JOB_COMPLETION_INDEX=", 0) == 0 ||
                          item.rfind("AWS_BATCH_", 0) == 0;
        if (!task) {
            env.push_back(item);
        }
    }
    env.insert(env.end(), extra.begin(), extra.end());
    return env;
}

/// A trisnap process running in the background, stdout and stderr to files in `dir`.
class Task {
public:
    Task(const TempDir& dir, const std::string& name, const std::vector<std::string>& args,
         const std::vector<std::string>& env_extra)
        : m_out(dir.path(name + ".out")), m_err(dir.path(name + ".err"))
    {
        std::vector<std::string> argv{TRISNAP_EXE};
        argv.insert(argv.end(), args.begin(), args.end());
        const std::vector<std::string> env = task_environment(env_extra);
        std::vector<char*> argp;
        std::vector<char*> envp;
        for (const std::string& a : argv) {
            argp.push_back(const_cast<char*>(a.c_str()));
        }
        for (const std::string& e : env) {
            envp.push_back(const_cast<char*>(e.c_str()));
        }
        argp.push_back(nullptr);
        envp.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 1, m_out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&actions, 2, m_err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        m_started = posix_spawn(&m_pid, argp[0], &actions, nullptr, argp.data(), envp.data()) == 0;
        posix_spawn_file_actions_destroy(&actions);
    }
    ~Task()
    {
        if (m_started && !m_waited) {
            kill(m_pid, SIGKILL);
            wait();
        }
    }
    RunOutput wait()
    {
        RunOutput r;
        int status = 0;
        if (m_started && waitpid(m_pid, &status, 0) == m_pid) {
            r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        m_waited = true;
        r.out = file_bytes(m_out);
        r.err = file_bytes(m_err);
        return r;
    }
    void signal(int sig) const { kill(m_pid, sig); }
    bool started() const { return m_started; }

private:
    std::string m_out;
    std::string m_err;
    pid_t m_pid = -1;
    bool m_started = false;
    bool m_waited = false;
};

/// Shards 0..n-1 as parallel processes with SLURM_ARRAY_TASK_ID/COUNT set; all must succeed.
void run_slurm_array(const TempDir& dir, const std::string& run_dir, int n)
{
    std::vector<std::unique_ptr<Task>> tasks;
    for (int i = 0; i < n; ++i) {
        tasks.push_back(std::make_unique<Task>(
            dir, "task" + std::to_string(i), std::vector<std::string>{"snap-tiles", run_dir, "--threads", "1"},
            std::vector<std::string>{"SLURM_ARRAY_TASK_ID=" + std::to_string(i), "SLURM_ARRAY_TASK_MIN=0",
                                     "SLURM_ARRAY_TASK_COUNT=" + std::to_string(n)}));
        ASSERT_TRUE(tasks.back()->started());
    }
    for (int i = 0; i < n; ++i) {
        const RunOutput r = tasks[static_cast<std::size_t>(i)]->wait();
        ASSERT_EQ(r.code, 0) << "shard " << i << ": " << r.err;
        EXPECT_EQ(r.err, "");
        EXPECT_NE(r.out.find("shard " + std::to_string(i) + " of " + std::to_string(n) + " (SLURM_ARRAY_TASK_ID)"),
                  std::string::npos) << r.out;
    }
}

/// Tiles with a committed result: result-N and seams-N (a task killed between the two commits
/// leaves a result alone, and that tile runs again).
std::size_t result_files(const std::string& run_dir)
{
    std::size_t n = 0;
    for (const auto& entry : fs::directory_iterator(run_dir)) {
        const std::string name = entry.path().filename().string();
        const bool result = name.rfind("result-", 0) == 0 && name.find(".tmp") == std::string::npos;
        n += result && fs::exists(run_dir + "/seams-" + name.substr(7)) ? 1 : 0;
    }
    return n;
}

/// The one-machine snap of `in` with `options`, written to `out`.
void snap_one_machine(const TempDir& dir, const std::string& in, const std::string& out,
                      const std::vector<std::string>& options)
{
    std::vector<std::string> args{"snap", in, out, "-q"};
    args.insert(args.end(), options.begin(), options.end());
    const RunOutput r = run_trisnap(dir, args);
    ASSERT_EQ(r.code, 0) << r.err;
}

void plan_run(const TempDir& dir, const std::string& in, const std::string& run_dir, const std::vector<std::string>& options)
{
    std::vector<std::string> args{"plan", in, run_dir};
    args.insert(args.end(), options.begin(), options.end());
    const RunOutput r = run_trisnap(dir, args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("planned "), std::string::npos) << r.out;
}

/// Each shard's marker: tiles and vertices; together they hold every planned tile once, each
/// task snapped exactly its own tiles (the shares are disjoint), and no shard holds more vertices
/// than the least loaded one plus the largest tile.
void expect_balanced_shares(const std::string& run_dir, int n)
{
    const nlohmann::json plan = read_json(run_dir + "/cluster.json");
    std::size_t tiles = 0;
    std::uint64_t most = 0;
    std::uint64_t least = UINT64_MAX;
    std::uint64_t vertices = 0;
    for (int i = 0; i < n; ++i) {
        const nlohmann::json s = read_json(run_dir + "/shard-" + std::to_string(i) + "-of-" + std::to_string(n));
        tiles += s["tiles"].get<std::size_t>();
        EXPECT_EQ(s["snapped"], s["tiles"]) << "shard " << i << " snapped other tiles than its own";
        vertices += s["vertices"].get<std::uint64_t>();
        most = std::max(most, s["vertices"].get<std::uint64_t>());
        least = std::min(least, s["vertices"].get<std::uint64_t>());
    }
    EXPECT_EQ(tiles, plan["tiles"].get<std::size_t>());
    EXPECT_EQ(vertices, plan["vertices"].get<std::uint64_t>());
    EXPECT_LE(most - least, plan["largest_tile_vertices"].get<std::uint64_t>());
}

void expect_sharded_equals_snap(const std::string& in, const std::vector<std::string>& options, int shards)
{
    TempDir dir;
    const std::string one = dir.path("one.gpkg");
    std::vector<std::string> with_report = options;
    with_report.insert(with_report.end(), {"--report", dir.path("one.json")});
    snap_one_machine(dir, in, one, with_report);
    const std::string run_dir = dir.path("run");
    plan_run(dir, in, run_dir, options);
    run_slurm_array(dir, run_dir, shards);
    expect_balanced_shares(run_dir, shards);
    const std::string out = dir.path("sharded.gpkg");
    const RunOutput r = run_trisnap(dir, {"stitch", run_dir, out, "-q", "--report", dir.path("stitch.json")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const std::string bytes = file_bytes(out);
    ASSERT_FALSE(bytes.empty());
    EXPECT_TRUE(bytes == file_bytes(one)) << "sharded output differs from the one-machine snap";
    const nlohmann::json report = read_json(dir.path("stitch.json"));
    const nlohmann::json single = read_json(dir.path("one.json"));
    EXPECT_EQ(report["counts"], single["counts"]);
    EXPECT_EQ(report["problems"], single["problems"]) << "the problems (seam notes 301 too) differ from the one-machine snap";
    EXPECT_EQ(report["tiling"]["seam_merges"], single["tiling"]["seam_merges"]);
    EXPECT_EQ(report["counts"]["input"], report["counts"]["written"].get<std::size_t>() + report["counts"]["rejected"].get<std::size_t>() +
                                             report["counts"]["dropped"].get<std::size_t>() + report["counts"]["unwritable"].get<std::size_t>());
    EXPECT_TRUE(fs::exists(run_dir + "/manifest.json")) << "stitch keeps RUN_DIR";
}

TEST(CliCluster, ShardsInParallelGiveTheBytesOfOneMachine)
{
    if (!exists(andorra())) {
        GTEST_SKIP() << "data set absent: " << andorra();
    }
    expect_sharded_equals_snap(andorra(), {"--tolerance", "1e-6", "--tile-size", "0.01"}, 3);
}

// Lines in small tiles: 52 seam merges, snapped again by stitch on its own machine.
TEST(CliCluster, SeamMergesInStitchGiveTheBytesOfOneMachine)
{
    if (!exists(monaco_pbf())) {
        GTEST_SKIP() << "data set absent: " << monaco_pbf();
    }
    expect_sharded_equals_snap(monaco_pbf(), {"--layer", "lines", "--tolerance", "1e-6", "--tile-size", "0.002"}, 4);
}

TEST(CliCluster, KilledShardRunAgainGivesTheSameBytes)
{
    if (!exists(monaco_pbf())) {
        GTEST_SKIP() << "data set absent: " << monaco_pbf();
    }
    const std::vector<std::string> options{"--layer", "lines", "--tolerance", "1e-6", "--tile-size", "0.002"};
    TempDir dir;
    const std::string one = dir.path("one.gpkg");
    snap_one_machine(dir, monaco_pbf(), one, options);
    const std::string run_dir = dir.path("run");
    plan_run(dir, monaco_pbf(), run_dir, options);
    const std::size_t planned = read_json(run_dir + "/cluster.json")["tiles"].get<std::size_t>();
    {
        Task victim(dir, "victim", {"snap-tiles", run_dir, "--threads", "1"},
                    {"SLURM_ARRAY_TASK_ID=0", "SLURM_ARRAY_TASK_COUNT=2"});
        ASSERT_TRUE(victim.started());
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (result_files(run_dir) < 5 && std::chrono::steady_clock::now() < deadline) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        victim.signal(SIGKILL);
        EXPECT_EQ(victim.wait().code, 128 + SIGKILL);
    }
    const std::size_t done = result_files(run_dir);
    ASSERT_GE(done, 5u);
    ASSERT_LT(done, planned / 2) << "the task finished before it was killed: nothing tested";
    EXPECT_FALSE(fs::exists(run_dir + "/shard-0-of-2")) << "a killed task must not mark its shard finished";
    {
        // SIGTERM (Slurm's signal on preemption, requeue and time limit) stops it between tiles.
        Task stopped(dir, "stopped", {"snap-tiles", run_dir, "--threads", "1"},
                     {"SLURM_ARRAY_TASK_ID=1", "SLURM_ARRAY_TASK_COUNT=2"});
        ASSERT_TRUE(stopped.started());
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (result_files(run_dir) < done + 5 && std::chrono::steady_clock::now() < deadline) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        stopped.signal(SIGTERM);
        const RunOutput r = stopped.wait();
        expect_error(r, 1, "interrupted by SIGTERM; the tiles snapped so far are kept: run this task again");
        EXPECT_FALSE(fs::exists(run_dir + "/shard-1-of-2"));
    }
    run_slurm_array(dir, run_dir, 2);
    EXPECT_GE(read_json(run_dir + "/shard-0-of-2")["done_before"].get<std::size_t>(), done)
        << "the tiles the killed task committed are not snapped again";
    for (const auto& entry : fs::directory_iterator(run_dir)) {
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
            << entry.path() << ": the killed task's temporary file outlived the tasks run after it";
    }
    const std::string out = dir.path("sharded.gpkg");
    const RunOutput r = run_trisnap(dir, {"stitch", run_dir, out, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(file_bytes(out) == file_bytes(one)) << "output after a killed task differs from the one-machine snap";
}

/// A fixture run directory of several tiles.
std::string small_run(const TempDir& dir, const std::vector<std::string>& more = {})
{
    const std::string in = write_snapping_gpkg(dir);
    const std::string run_dir = dir.path("run");
    std::vector<std::string> options{"--tolerance", "0.01", "--tile-size", "5"};
    options.insert(options.end(), more.begin(), more.end());
    plan_run(dir, in, run_dir, options);
    return run_dir;
}

/// The tile ids of stitch's "N of M tiles have no result: a, b, c and K more;" message.
std::vector<std::size_t> listed_tiles(const std::string& message)
{
    const std::string head = "have no result: ";
    const std::size_t from = message.find(head) + head.size();
    std::istringstream list(message.substr(from, message.find(';', from) - from));
    std::vector<std::size_t> tiles;
    for (std::string item; std::getline(list, item, ',');) {
        tiles.push_back(std::stoul(item)); // " 12" and " 12 and 4 more" both read as 12
    }
    return tiles;
}

TEST(CliCluster, StitchWithAMissingShardListsTilesAndShards)
{
    TempDir dir;
    const std::string run_dir = small_run(dir, {"--num-shards", "3"});
    const std::size_t planned = read_json(run_dir + "/cluster.json")["tiles"].get<std::size_t>();
    ASSERT_GE(planned, 3u);
    for (const char* shard : {"0", "2"}) {
        const RunOutput r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", shard, "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const std::size_t missing = planned - result_files(run_dir);
    ASSERT_GT(missing, 0u);
    const std::string out = dir.path("out.gpkg");
    RunOutput r = run_trisnap(dir, {"stitch", run_dir, out});
    expect_error(r, 1, std::to_string(missing) + " of " + std::to_string(planned) + " tiles have no result: ");
    EXPECT_NE(r.err.find("shard 1 of 3 has not finished: run it (trisnap snap-tiles " + run_dir +
                         " --shard 1 --num-shards 3), then stitch"), std::string::npos) << r.err;
    for (std::size_t tile : listed_tiles(r.err)) {
        EXPECT_FALSE(fs::exists(run_dir + "/result-" + std::to_string(tile))) << "tile " << tile << " is listed";
    }
    EXPECT_FALSE(fs::exists(out));
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"stitch", run_dir, out, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(read_layer(out).empty());
}

TEST(CliCluster, RunDirOfAnotherVersionOrInputIsRefused)
{
    TempDir dir;
    const std::string run_dir = small_run(dir);
    RunOutput r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    // The same RUN_DIR cannot be planned over.
    r = run_trisnap(dir, {"plan", dir.path("in.gpkg"), run_dir, "--tolerance", "0.01"});
    expect_error(r, 2, "holds an earlier run");
    // The input changed after the plan.
    fs::last_write_time(dir.path("in.gpkg"), fs::last_write_time(dir.path("in.gpkg")) + std::chrono::seconds(5));
    r = run_trisnap(dir, {"stitch", run_dir, dir.path("out.gpkg")});
    expect_error(r, 2, run_dir + ": the input changed since trisnap plan (" + fs::weakly_canonical(dir.path("in.gpkg")).string());
    EXPECT_FALSE(fs::exists(dir.path("out.gpkg")));
    // Another build of this version (a commit or an edit apart), then none recorded (a plan
    // made before builds were recorded), then another version.
    const std::string manifest = run_dir + "/manifest.json";
    const nlohmann::json planned = read_json(manifest);
    const std::string build = planned.value("build", std::string());
    ASSERT_EQ(build.rfind(planned["version"].get<std::string>() + "+", 0), 0u) << "build id: " << build;
    r = run_trisnap(dir, {"--version"});
    EXPECT_NE(r.out.find("(build " + build + ")"), std::string::npos) << "--version names the build: " << r.out;
    nlohmann::json m = planned;
    m["build"] = "0.1.0+g0123456789ab";
    std::ofstream(manifest) << m.dump(2);
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1"});
    expect_error(r, 2, run_dir + ": planned by trisnap build 0.1.0+g0123456789ab, this is build " + build +
                           "; plan it again with this build, or run every step with the build that planned it");
    r = run_trisnap(dir, {"stitch", run_dir, dir.path("out.gpkg")});
    expect_error(r, 2, "planned by trisnap build 0.1.0+g0123456789ab, this is build " + build);
    m.erase("build");
    std::ofstream(manifest) << m.dump(2);
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1"});
    expect_error(r, 2, "planned by trisnap build (none recorded), this is build " + build);
    m = planned;
    m["version"] = "0.0.1";
    std::ofstream(manifest) << m.dump(2);
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1"});
    expect_error(r, 2, run_dir + ": planned by trisnap 0.0.1, this is trisnap ");
    r = run_trisnap(dir, {"stitch", run_dir, dir.path("out.gpkg")});
    expect_error(r, 2, "planned by trisnap 0.0.1");
    // The manifest as planned is accepted again (only the build and version were the cause).
    std::ofstream(manifest) << planned.dump(2);
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0", "--num-shards", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
}

/// A PID that names no process: a child that ran and was reaped.
pid_t dead_pid()
{
    pid_t pid = -1;
    char arg0[] = "true";
    char* argv[] = {arg0, nullptr};
    if (posix_spawnp(&pid, "true", nullptr, nullptr, argv, environ) != 0) {
        return -1;
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return pid;
}

std::string this_host()
{
    char name[256] = {};
    gethostname(name, sizeof name - 1);
    return name;
}

// A task killed while writing leaves NAME.tmp-HOST-PID; the next task on that host removes the
// ones whose process is gone, and keeps those of live processes and of other hosts.
TEST(CliCluster, StaleTemporariesOfKilledTasksOnThisHostAreRemoved)
{
    TempDir dir;
    const std::string run_dir = small_run(dir, {"--num-shards", "2"});
    const pid_t dead = dead_pid();
    ASSERT_GT(dead, 0);
    ASSERT_NE(kill(dead, 0), 0) << "pid " << dead << " was taken again";
    const std::string host = this_host();
    const std::vector<std::string> stale{"result-0.tmp-" + host + "-" + std::to_string(dead),
                                         "seams-1.tmp-" + host + "-" + std::to_string(dead)};
    const std::vector<std::string> kept{"result-2.tmp-" + host + "-" + std::to_string(getpid()), // a live process
                                        "result-3.tmp-" + host + "x-" + std::to_string(dead),    // another host
                                        "result-4.tmp-" + host + "-" + std::to_string(dead) + "x"}; // not a PID
    for (const std::string& name : stale) {
        std::ofstream(run_dir + "/" + name) << "partial";
    }
    for (const std::string& name : kept) {
        std::ofstream(run_dir + "/" + name) << "partial";
    }
    RunOutput r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "0"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("; removed 2 temporary files left by killed tasks on this host\n"), std::string::npos) << r.out;
    for (const std::string& name : stale) {
        EXPECT_FALSE(fs::exists(run_dir + "/" + name)) << name << " is stale: its process is gone";
    }
    for (const std::string& name : kept) {
        EXPECT_TRUE(fs::exists(run_dir + "/" + name)) << name << " must be kept";
    }
    EXPECT_EQ(read_json(run_dir + "/shard-0-of-2")["stale_temporaries_removed"], 2);
    r = run_trisnap(dir, {"snap-tiles", run_dir, "--shard", "1", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_json(run_dir + "/shard-1-of-2")["stale_temporaries_removed"], 0);
    r = run_trisnap(dir, {"stitch", run_dir, dir.path("out.gpkg"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(read_layer(dir.path("out.gpkg")).empty());
}

TEST(CliCluster, PlanTakesOneLayerAndItsHelpSaysSo)
{
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"plan", "--help"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("one layer per cluster run"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("repeat it"), std::string::npos) << "plan's help offers several layers: " << r.out;
    const std::string in = write_snapping_gpkg(dir);
    r = run_trisnap(dir, {"plan", in, dir.path("run"), "--tolerance", "0.01", "--layer", "a", "--layer", "b"});
    expect_error(r, 2, "trisnap plan takes one --layer");
}

TEST(CliCluster, OtherDirectoriesAreRefused)
{
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"snap-tiles", dir.path("nowhere"), "--shard", "0"});
    expect_error(r, 2, dir.path("nowhere") + ": no such run directory");
    fs::create_directories(dir.path("empty"));
    r = run_trisnap(dir, {"stitch", dir.path("empty"), dir.path("o.gpkg")});
    expect_error(r, 2, "not a trisnap run directory (no manifest.json)");
    // The work directory of a snap that stopped after its read phase.
    const std::string in = write_snapping_gpkg(dir);
    const std::string work = dir.path("work");
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--work-dir", work, "--memory-limit", "1MiB"});
    ASSERT_EQ(r.code, 2) << r.err;
    ASSERT_TRUE(fs::exists(work + "/manifest.json")) << "the snap kept no work directory";
    r = run_trisnap(dir, {"snap-tiles", work, "--shard", "0", "--num-shards", "1"});
    expect_error(r, 2, "the work directory of a `trisnap snap` run, not a run directory made by trisnap plan");
}

TEST(CliCluster, ShardIndexComesFromTheArrayVariables)
{
    TempDir dir;
    const std::string run_dir = small_run(dir, {"--num-shards", "2"});
    const std::vector<std::string> args{"snap-tiles", run_dir};
    struct Case {
        std::vector<std::string> env;
        std::string expected; ///< in stdout (exit 0) or in the error (exit 2)
        int code;
    };
    const std::vector<Case> cases{
        {{"SLURM_ARRAY_TASK_ID=5", "SLURM_ARRAY_TASK_MIN=4", "SLURM_ARRAY_TASK_COUNT=2"}, "shard 1 of 2 (SLURM_ARRAY_TASK_ID)", 0},
        {{"JOB_COMPLETION_INDEX=0"}, "shard 0 of 2 (JOB_COMPLETION_INDEX)", 0},
        {{"AWS_BATCH_JOB_ARRAY_INDEX=1"}, "shard 1 of 2 (AWS_BATCH_JOB_ARRAY_INDEX)", 0},
        {{}, "no shard index: give --shard I, or run as an array task", 2},
        {{"SLURM_ARRAY_TASK_ID=3", "SLURM_ARRAY_TASK_COUNT=3"}, "shard 3 from SLURM_ARRAY_TASK_ID (less SLURM_ARRAY_TASK_MIN) is outside 0..2", 2},
        {{"JOB_COMPLETION_INDEX=-1"}, "JOB_COMPLETION_INDEX='-1' is not a task index", 2},
        {{"AWS_BATCH_JOB_ARRAY_INDEX=2"}, "shard 2 from AWS_BATCH_JOB_ARRAY_INDEX is outside 0..1 (2 shards from the plan)", 2},
    };
    for (const Case& c : cases) {
        Task task(dir, "task", args, c.env);
        const RunOutput r = task.wait();
        if (c.code == 0) {
            ASSERT_EQ(r.code, 0) << r.err;
            EXPECT_NE(r.out.find(c.expected), std::string::npos) << r.out;
        } else {
            expect_error(r, c.code, c.expected);
        }
    }
    EXPECT_TRUE(fs::exists(run_dir + "/shard-0-of-2"));
    EXPECT_TRUE(fs::exists(run_dir + "/shard-1-of-2"));
}

} // namespace
} // namespace trisnap::test
