// `trisnap snap-tiles RUN_DIR [--shard I] [--num-shards N]`: one array task of a cluster run
// (app/run_dir.hpp, app/shards.hpp). Snaps the tiles of shard I that have no result yet, each
// committed by temp file + rename, so a task that was killed or requeued simply runs again (and
// removes the temporary files the killed one left, when it ran on this host).
// Needs only RUN_DIR, never the input. Leaves shard-I-of-N when its share is done.
#include "app/command.hpp"
#include "app/memory.hpp"
#include "app/options.hpp"
#include "app/run_dir.hpp"
#include "app/run_phases.hpp"
#include "app/shards.hpp"
#include "app/text.hpp"
#include "config/errors.hpp"
#include "config/size.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <iostream>

namespace trisnap {
namespace {

const char* env(const char* name) { return std::getenv(name); }

/// --threads, else the CPUs Slurm gave the task, else all cores.
int task_threads(std::optional<int> flag)
{
    if (flag) {
        return *flag;
    }
    const char* slurm = env("SLURM_CPUS_PER_TASK");
    return slurm ? std::max(0, std::atoi(slurm)) : 0;
}

/// --memory-limit, else the plan's, else half of the memory (or of the job's cgroup limit).
RunBudget task_budget(const RunDir& dir, const std::optional<std::string>& flag)
{
    RunBudget b;
    b.on_disk = true;
    b.work_dir = dir.path();
    if (flag) {
        b.memory_limit = parse_size(*flag, "--memory-limit");
        b.reason = "--memory-limit " + format_size(b.memory_limit);
    } else if (dir.config().run.memory_limit > 0) {
        b.memory_limit = dir.config().run.memory_limit;
        b.reason = "the plan's --memory-limit " + format_size(b.memory_limit);
    } else {
        b.memory_limit = physical_memory() / 2;
        b.reason = "half of the memory (" + format_size(b.memory_limit) + ")";
    }
    return b;
}

struct Share {
    std::vector<bool> mine;     ///< per plan leaf
    std::size_t tiles = 0;
    std::uint64_t vertices = 0;
    std::size_t done_before = 0;
    std::size_t snapped = 0;    ///< tiles this process snapped
    std::size_t stale = 0;      ///< temporary files of killed tasks removed at the start
};

Share share_of(const stitch::TiledRun& run, const ShardIndex& shard)
{
    const std::vector<ShardTile> tiles = planned_tiles(run.layout());
    const std::vector<std::size_t> owner = assign_shards(tiles, shard.count);
    Share s;
    s.mine.assign(run.layout().plan.size(), false);
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        if (owner[k] == shard.index) {
            s.mine[tiles[k].id] = true;
            ++s.tiles;
            s.vertices += tiles[k].vertices;
        }
    }
    std::size_t missing = 0;
    for (std::size_t g : run.missing()) {
        missing += g < s.mine.size() && s.mine[g] ? 1 : 0;
    }
    s.done_before = s.tiles - missing;
    return s;
}

class SnapTilesCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("snap-tiles", "snap one shard's tiles of a run directory made by "
                                                            "trisnap plan (one array task; needs no input access)");
        app->add_option("RUN_DIR", m_run_dir, "the run directory made by trisnap plan");
        app->add_option("--shard", m_shard, "this task's shard, 0..N-1 (default: SLURM_ARRAY_TASK_ID - "
                                            "SLURM_ARRAY_TASK_MIN, JOB_COMPLETION_INDEX or AWS_BATCH_JOB_ARRAY_INDEX)");
        app->add_option("--num-shards", m_num_shards, "the number of shards N (default: SLURM_ARRAY_TASK_COUNT, "
                                                      "else the number trisnap plan recorded)");
        app->add_option("--memory-limit", m_args.memory_limit, "memory this task may use, e.g. 4GiB (default: the "
                                                               "plan's --memory-limit, else half of the memory)");
        app->add_option("--threads", m_args.threads, "tiles snapped at once (default: SLURM_CPUS_PER_TASK, else all cores)");
        add_logging_options(*app, m_args);
        return app;
    }

    int run() override
    {
        setup_logging(m_args.verbose, m_args.quiet);
        if (m_run_dir.empty()) {
            throw argument_error("missing RUN_DIR: trisnap snap-tiles RUN_DIR [--shard I --num-shards N]");
        }
        const auto start = std::chrono::steady_clock::now();
        InterruptGuard interrupt;
        RunDir dir = RunDir::open(m_run_dir);
        const ShardIndex shard = resolve_shard(m_shard, m_num_shards, dir.record().shards, env);
        const std::size_t stale = dir.remove_stale_temporaries();
        const RunBudget budget = task_budget(dir, m_args.memory_limit);
        stitch::TilingOptions tiling = dir.tiling();
        tiling.threads = task_threads(m_args.threads);
        const ThreadLimit limit(tiling.threads);
        Progress progress(m_args.progress, m_args.json_progress);
        RunPhases phases(dir.work(), budget, progress, interrupt, dir.options(), tiling);
        phases.set_interrupt_message("the tiles snapped so far are kept: run this task again to finish its shard");
        if (!phases.load_read()) {
            throw argument_error(m_run_dir + ": the plan did not finish (no read.bin); run trisnap plan again");
        }
        phases.open_tiles();
        phases.spool();
        Share share = share_of(phases.tiles(), shard);
        phases.snap([&](std::size_t g) { return g < share.mine.size() && share.mine[g]; });
        share.snapped = phases.tiles().stats().tile_runs;
        share.stale = stale;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        dir.mark_finished(shard.index, shard.count, summary_json(shard, share, seconds));
        if (m_args.quiet == 0) {
            std::cout << fmt::format("shard {} of {} ({}): {} ({} input vertices), {} snapped now, {} done before; "
                                     "{:.2f} s, peak memory {}{}\n", shard.index, shard.count, shard.source,
                                     count_of(share.tiles, "tile"), share.vertices, share.snapped,
                                     share.done_before, seconds, format_size(peak_rss()), stale_note(share.stale));
        }
        return 0;
    }

private:
    static std::string summary_json(const ShardIndex& shard, const Share& share, double seconds)
    {
        const std::string host = host_name();
        const nlohmann::ordered_json j = {{"shard", shard.index}, {"shards", shard.count}, {"tiles", share.tiles},
                                          {"vertices", share.vertices}, {"snapped", share.snapped}, {"done_before", share.done_before},
                                          {"seconds", seconds}, {"peak_rss", peak_rss()},
                                          {"host", host.empty() ? std::string("unknown") : host},
                                          {"stale_temporaries_removed", share.stale}};
        return j.dump(2);
    }

    static std::string stale_note(std::size_t stale)
    {
        return stale == 0 ? std::string() : fmt::format("; removed {} left by killed tasks on this host",
                                                         count_of(stale, "temporary file"));
    }

    SnapArgs m_args;
    std::string m_run_dir;
    std::optional<long long> m_shard;
    std::optional<long long> m_num_shards;
};

} // namespace

std::unique_ptr<Command> make_snap_tiles_command() { return std::make_unique<SnapTilesCommand>(); }

} // namespace trisnap
