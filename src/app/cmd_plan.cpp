// `trisnap plan IN RUN_DIR --tolerance T ...`: the first step of a cluster run (app/run_dir.hpp).
// Reads the layer once into RUN_DIR (storage every node of the cluster sees), plans the tiles
// and fills their buckets, records the resolved settings, and prints the number of tiles, a
// suggested number of array tasks and the memory a task needs. The tile plan is the one
// `trisnap snap` makes with the same options, so the sharded output has the same bytes.
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/run_dir.hpp"
#include "app/run_phases.hpp"
#include "app/shards.hpp"
#include "app/text.hpp"
#include "config/errors.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <thread>

namespace trisnap {
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;
/// What a snap-tiles task holds besides its tiles (measured: 30-40 MiB on Andorra and Monaco).
constexpr std::uint64_t k_task_base = 64 * k_mib;

/// A plain file given by a relative path becomes absolute: later steps run elsewhere.
std::string absolute_input(const std::string& input)
{
    std::error_code ec;
    if (!std::filesystem::exists(input, ec)) {
        return input; // a GDAL connection string or virtual path, kept as given
    }
    return std::filesystem::absolute(input, ec).string();
}

PlanRecord make_record(const stitch::TileLayout& layout, std::optional<long long> shards)
{
    const std::vector<ShardTile> tiles = planned_tiles(layout);
    PlanRecord r;
    r.tiles = tiles.size();
    for (const ShardTile& t : tiles) {
        r.vertices += t.vertices;
        r.largest = std::max(r.largest, t.vertices);
    }
    r.suggested = suggest_shards(tiles);
    r.shards = shards ? static_cast<std::size_t>(*shards) : r.suggested;
    return r;
}

/// The --memory-limit under which one task runs `threads` of the largest tiles at once (the
/// limit keeps a quarter and 16 MiB for GDAL and buffers, app/budget.hpp), as the flag takes it.
std::string task_memory(std::uint64_t largest, unsigned threads)
{
    const stitch::MemoryModel model;
    const std::uint64_t tiles = threads * model.tile_bytes(largest);
    const std::uint64_t limit = (k_task_base + tiles + 16 * k_mib) * 4 / 3;
    return fmt::format("{}MiB", (limit + k_mib - 1) / k_mib);
}

void print_record(std::ostream& out, const std::string& run_dir, const PlanRecord& r)
{
    out << fmt::format("planned {} ({} input vertices, the largest tile {}) in {}\n", count_of(r.tiles, "tile"),
                       r.vertices, r.largest, run_dir);
    out << fmt::format("shards: {} recorded (suggested {}: at least {} tiles and {} vertices per task)\n", r.shards,
                       r.suggested, k_tiles_per_shard, k_vertices_per_shard);
    out << fmt::format("memory per task: --memory-limit {} with 1 thread, {} with 2, {} with 4\n",
                       task_memory(r.largest, 1), task_memory(r.largest, 2), task_memory(r.largest, 4));
    out << fmt::format("next: trisnap snap-tiles {0} --shard I --num-shards {1} for I in 0..{2} (or "
                       "scripts/slurm/submit), then trisnap stitch {0} OUT\n", run_dir, r.shards, r.shards - 1);
}

class PlanCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("plan", "read a layer into a run directory and plan its tiles for "
                                                      "snap-tiles tasks (a snap split across a cluster)");
        add_input_options(*app, m_args);
        // A cluster run is one layer (check_arguments): snap's "repeat it" does not hold here.
        app->get_option("--layer")->description("input layer (default: the only polygon/line layer); one layer per "
                                                "cluster run (several layers together: trisnap snap)");
        app->add_option("RUN_DIR", m_run_dir, "the run directory to make, on storage every task sees (new or empty)");
        add_engine_options(*app, m_args);
        add_settings_options(*app, m_args);
        add_tiling_options(*app, m_args);
        app->add_option("--threads", m_args.threads, "threads of this command and of each task, for the tile "
                                                     "budget under --memory-limit; 0 = all cores ([run] threads)");
        app->add_option("--memory-limit", m_args.memory_limit, "memory of this command and of each snap-tiles task "
                                                               "(their default), e.g. 4GiB ([run] memory_limit)");
        app->add_option("--num-shards", m_num_shards, "the number of array tasks to record (default: the suggestion)");
        app->add_flag("--resume", m_args.resume, "continue a plan of this RUN_DIR that stopped (same command and input)");
        app->add_flag("--allow-collapse,--force", m_args.allow_collapse, "let stitch write OUT even when snapping drops "
                                                                         "much of the layer ([run] allow_collapse)");
        add_logging_options(*app, m_args);
        return app;
    }

    int run() override
    {
        const std::optional<Config> resolved = start_snap_command(m_args);
        if (!resolved) {
            return 0;
        }
        check_arguments();
        InterruptGuard interrupt;
        const Config& config = *resolved;
        const ThreadLimit limit(config.run.threads);
        SnapArgs args = m_args;
        args.input = absolute_input(m_args.input);
        args.work_dir = m_run_dir;
        const RunBudget budget = choose_budget(args, config);
        WorkDir work = WorkDir::on_disk(m_run_dir, m_args.resume);
        apply_gdal_budget(budget);
        Plan plan = make_input_plan(args, config);
        work.bind(cluster_manifest(plan, args));
        Progress progress(m_args.progress, m_args.json_progress);
        RunPhases phases(work, budget, progress, interrupt, plan.options, plan.tiling);
        phases.read(plan);
        phases.open_tiles();
        phases.spool();
        const PlanRecord record = make_record(phases.tiles().layout(), m_num_shards);
        save_plan_record(work.store(), record);
        work.keep();
        if (m_args.quiet == 0) {
            print_record(std::cout, m_run_dir, record);
        }
        return 0;
    }

private:
    void check_arguments() const
    {
        if (m_run_dir.empty()) {
            throw argument_error("missing RUN_DIR: trisnap plan IN RUN_DIR --tolerance T");
        }
        if (m_args.layers.size() > 1) {
            throw argument_error("trisnap plan takes one --layer: a cluster run snaps one layer (several layers in one "
                                 "run are for trisnap snap)");
        }
        if (m_num_shards && (*m_num_shards < 1 || *m_num_shards > 1000000)) {
            throw argument_error(fmt::format("--num-shards must be in 1..1000000, got {}", *m_num_shards));
        }
    }

    SnapArgs m_args;
    std::string m_run_dir;
    std::optional<long long> m_num_shards;
};

} // namespace

std::unique_ptr<Command> make_plan_command() { return std::make_unique<PlanCommand>(); }

} // namespace trisnap
