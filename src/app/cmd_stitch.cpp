// `trisnap stitch RUN_DIR OUT`: the last step of a cluster run (app/run_dir.hpp). Refuses while
// a tile has no result (listing the tiles and the shards to run again); else re-opens the input
// (refused when its files changed since the plan), checks the seams, merges and snaps again the
// tiles that disagree (on this machine), and writes OUT with the input's attributes: the same
// bytes `trisnap snap` writes with the same options. RUN_DIR is kept (remove it with rm -r once
// OUT is checked); running stitch again writes the same OUT.
#include "app/collapse_guard.hpp"
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/pipeline.hpp"
#include "app/run_dir.hpp"
#include "app/run_phases.hpp"
#include "app/shards.hpp"
#include "app/report.hpp"
#include "app/text.hpp"
#include "config/errors.hpp"
#include "config/size.hpp"
#include "io/commit_group.hpp"
#include "io/io_error.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <set>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The number of shards to name in a message: --num-shards, else the one the finished tasks
/// ran under (when they agree), else the plan's.
std::size_t shards_to_name(const RunDir& dir, std::optional<long long> flag)
{
    if (flag) {
        return static_cast<std::size_t>(*flag);
    }
    const std::vector<std::size_t> seen = dir.shard_counts_seen();
    return seen.size() == 1 ? seen.front() : dir.record().shards;
}

template <class T>
T load_work_file(const tiling::WorkStore& store, const std::string& name)
{
    const std::string bytes = store.get(name);
    tiling::ByteReader reader(bytes, name.c_str());
    return T::load(reader);
}

/// Throws io_error (exit 1) listing the planned tiles without a result and their shards. A tile
/// merged at a seam by an earlier stitch counts as done (its leaves all had results then).
void check_finished(RunDir& dir, std::optional<long long> shards_flag)
{
    const tiling::WorkStore& store = dir.work().store();
    const auto layout = load_work_file<stitch::TileLayout>(store, stitch::files::layout);
    const auto groups = load_work_file<stitch::Groups>(store, stitch::files::groups);
    const std::vector<ShardTile> tiles = planned_tiles(layout);
    const std::size_t shards = std::max<std::size_t>(shards_to_name(dir, shards_flag), 1);
    const std::vector<std::size_t> owner = assign_shards(tiles, shards);
    std::vector<std::size_t> missing;
    std::set<std::size_t> rerun;
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        const std::size_t g = groups.of_leaf[tiles[k].id];
        if (g < layout.plan.size() && !(store.exists(stitch::files::result(g)) && store.exists(stitch::files::seams(g)))) {
            missing.push_back(tiles[k].id);
            rerun.insert(owner[k]);
        }
    }
    if (missing.empty()) {
        return;
    }
    const std::vector<std::size_t> to_run(rerun.begin(), rerun.end());
    const bool one = to_run.size() == 1;
    throw io_error(dir.path(), "", fmt::format("{} of {} have no result: {}; shard{} {} of {} {} not finished: run {} "
                                               "(trisnap snap-tiles {} --shard {} --num-shards {}), then stitch",
                                               missing.size(), count_of(tiles.size(), "tile"), list_numbers(missing),
                                               one ? "" : "s", list_numbers(to_run, 50), shards, one ? "has" : "have",
                                               one ? "it" : "them", dir.path(), one ? std::to_string(to_run[0]) : "I",
                                               shards));
}

class StitchCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("stitch", "check the seams of a run directory's tiles, snap again where "
                                                        "they disagree, and write OUT (the last step of a cluster run)");
        app->add_option("RUN_DIR", m_run_dir, "the run directory made by trisnap plan, its tiles snapped by snap-tiles");
        add_output_options(*app, m_args, true);
        app->add_flag("--strict", m_args.strict, "exit with code 3 when any problem is reported");
        app->add_option("--threads", m_args.threads, "worker threads for GDAL and oneTBB; 0 = all cores");
        app->add_option("--memory-limit", m_args.memory_limit, "memory this command may use, e.g. 4GiB (default: "
                                                               "the plan's, else as trisnap snap decides)");
        app->add_option("--num-shards", m_num_shards, "the number of shards, to name those to run again "
                                                      "(default: the finished tasks', else the plan's)");
        add_logging_options(*app, m_args);
        return app;
    }

    int run() override
    {
        setup_logging(m_args.verbose, m_args.quiet);
        check_arguments();
        const auto start = Clock::now();
        InterruptGuard interrupt; // from here to the end: no moment of the run gets a signal's default action
        RunDir dir = RunDir::open(m_run_dir);
        check_finished(dir, m_num_shards);
        const SnapArgs args = snap_args(dir);
        Config config = dir.config();
        config.run.threads = m_args.threads.value_or(0);
        config.run.allow_collapse = config.run.allow_collapse || m_args.allow_collapse;
        if (m_args.memory_limit) {
            config.run.memory_limit = parse_size(*m_args.memory_limit, "--memory-limit");
        }
        const ThreadLimit limit(config.run.threads);
        const RunBudget budget = choose_budget(args, config);
        apply_gdal_budget(budget);
        Plan plan = make_plan(args, config);
        plan.write.index_boxes = index_boxes(budget.memory_limit);
        dir.check_input(plan);
        // OUT and the report go into place together, or neither; the run directory is not an output.
        plan.write.protected_files.refuse_tree(dir.path(), "RUN_DIR");
        CommitGroup outputs;
        plan.write.commit_group = &outputs;
        const RunResult result = stitch_and_write(dir, budget, plan, interrupt);
        const double total = since(start);
        if (!args.report.empty()) {
            stage_report(outputs, args.report, plan, result, total);
        }
        commit_outputs(outputs, interrupt);
        plan.write.commit_group = nullptr;
        const int code = deliver_run(args, plan, result, total);
        spdlog::info("run directory {} kept; remove it with rm -r once the output is checked", dir.path());
        interrupt.warn_if_too_late();
        return code;
    }

private:
    void check_arguments() const
    {
        if (m_run_dir.empty() || m_args.output.empty()) {
            throw argument_error(std::string("missing ") + (m_run_dir.empty() ? "RUN_DIR" : "OUT") +
                                 ": trisnap stitch RUN_DIR OUT");
        }
        if (m_num_shards && *m_num_shards < 1) {
            throw argument_error(fmt::format("--num-shards must be >= 1, got {}", *m_num_shards));
        }
    }

    /// The plan's input and settings, this command's output options.
    SnapArgs snap_args(const RunDir& dir) const
    {
        SnapArgs args = m_args;
        const SnapArgs& planned = dir.input_args();
        args.input = planned.input;
        args.layers = planned.layers;
        args.where = planned.where;
        args.bbox = planned.bbox;
        args.open_options = planned.open_options;
        args.work_dir = dir.path();
        return args;
    }

    RunResult stitch_and_write(RunDir& dir, const RunBudget& budget, Plan& plan, InterruptGuard& interrupt) const
    {
        Progress progress(m_args.progress, m_args.json_progress);
        RunPhases phases(dir.work(), budget, progress, interrupt, plan.options, plan.tiling);
        if (!phases.load_read()) {
            throw argument_error(dir.path() + ": the plan did not finish (no read.bin); run trisnap plan again");
        }
        plan.write.renumber = renumbered_layers(phases.result());
        LayerWriter writer(plan.write, plan.layers);
        phases.open_tiles();
        const auto snap_start = Clock::now();
        phases.spool();
        const std::size_t leaves = phases.tiles().layout().plan.size();
        const std::vector<std::size_t> missing = phases.tiles().missing();
        if (std::any_of(missing.begin(), missing.end(), [&](std::size_t g) { return g >= leaves; })) {
            // Tiles merged by a stitch that stopped before their results were in.
            phases.snap([&](std::size_t g) { return g >= leaves; });
        }
        phases.stitch();
        phases.result().seconds_snap = since(snap_start);
        guard_collapse(plan, phases);
        phases.write(plan, writer);
        return phases.finish();
    }

    SnapArgs m_args;
    std::string m_run_dir;
    std::optional<long long> m_num_shards;
};

} // namespace

std::unique_ptr<Command> make_stitch_command() { return std::make_unique<StitchCommand>(); }

} // namespace trisnap
