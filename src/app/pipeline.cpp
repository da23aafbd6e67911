#include "app/pipeline.hpp"

#include "app/memory.hpp"
#include "app/phases.hpp"
#include "app/version.hpp"
#include "config/errors.hpp"
#include "io/io_error.hpp"
#include "io/writer.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::uint64_t k_mib = 1024 * 1024;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

class Pipeline {
public:
    Pipeline(Plan& plan, WorkDir& work, const RunBudget& budget, Progress& progress)
        : m_plan(plan), m_work(work), m_budget(budget), m_progress(progress)
    {
        m_result.budget = budget;
        m_result.resumed = work.resumed();
        m_result.tiled = !plan.tiling.plan.single;
    }
    RunResult run();

private:
    template <class F>
    void phase(const char* name, F&& body)
    {
        const auto start = Clock::now();
        body();
        m_result.phases.push_back(PhaseRecord{name, since(start), peak_rss()});
        m_result.spool_bytes = std::max(m_result.spool_bytes, m_work.bytes());
        spdlog::info("{}: {:.2f} s, peak memory {}, work files {}", name, m_result.phases.back().seconds,
                     format_size(peak_rss()), format_size(m_work.bytes()));
    }
    ReadSummary read();
    void check_disk(const stitch::SpoolMeta& meta) const;
    std::uint64_t memory_pool() const;
    void snap_tiles(stitch::TiledRun& run, const stitch::SpoolMeta& meta);
    [[noreturn]] void too_small(const stitch::budget_error& e) const;

    Plan& m_plan;
    WorkDir& m_work;
    const RunBudget& m_budget;
    Progress& m_progress;
    RunResult m_result;
    InterruptGuard m_interrupt;
    stitch::MemoryModel m_model;
};

// With a limit, the plan's sample and the FID check's buffer take a sixteenth of it each;
// without, the sample holds up to 16 M vertices (256 MiB).
ReadSummary Pipeline::read()
{
    ReadSummary s;
    if (m_work.resumed() && load_read(m_work.store(), s)) {
        spdlog::info("read: taken from the work directory (resumed)");
        return s;
    }
    const std::uint64_t limit = m_budget.memory_limit;
    const std::size_t sample_cap = limit ? static_cast<std::size_t>(limit / 16 / 16) : std::size_t{16} << 20;
    const std::size_t fid_buffer = limit ? static_cast<std::size_t>(limit / 16 / 8) : std::numeric_limits<std::size_t>::max();
    return read_layer(m_plan, m_work.store(), sample_cap, fid_buffer, m_progress, m_interrupt);
}

// The spool needs about features.bin again for the buckets and as much for the results.
void Pipeline::check_disk(const stitch::SpoolMeta& meta) const
{
    if (!m_work.on_disk()) {
        return;
    }
    const std::uint64_t features = m_work.store().total_bytes();
    const std::uint64_t need = 2 * features + 64 * k_mib;
    const std::uint64_t free = m_work.store().free_space();
    if (free < need) {
        throw io_error(m_work.path(), "", fmt::format("not enough free disk for the work files: about {} more are needed "
                                                      "for {} features, {} are free; give --work-dir on a larger disk",
                                                      format_size(need), meta.spooled, format_size(free)));
    }
}

// What the tiles in flight may take: the limit less what the process holds now and the margin
// for GDAL's caches and the buffers.
std::uint64_t Pipeline::memory_pool() const
{
    if (m_budget.memory_limit == 0) {
        return 0;
    }
    const std::uint64_t held = current_rss() + reserved_margin(m_budget);
    const std::uint64_t least = m_model.tile_bytes(1000);
    if (m_budget.memory_limit < held + least) {
        throw argument_error(fmt::format("--memory-limit {} is too small: the process holds {} before any tile, and the "
                                         "smallest tile needs {}; the smallest limit that would work is about {}",
                                         format_size(m_budget.memory_limit), format_size(held), format_size(least),
                                         format_size(held + m_model.tile_bytes(20000))));
    }
    return m_budget.memory_limit - held;
}

// The smallest limit under which the tile that did not fit would run alone.
void Pipeline::too_small(const stitch::budget_error& e) const
{
    const std::uint64_t held = current_rss() + reserved_margin(m_budget);
    const std::uint64_t need = held + m_model.tile_bytes(e.vertices());
    throw argument_error(fmt::format("--memory-limit {} is too small: {}; the smallest limit that would work is about {}",
                                     format_size(m_budget.memory_limit), e.what(), format_size(need + need / 8)));
}

void Pipeline::snap_tiles(stitch::TiledRun& run, const stitch::SpoolMeta& meta)
{
    auto on_tiles = [&](std::uint64_t done, std::uint64_t) { m_progress.update(static_cast<std::int64_t>(done)); };
    try {
        phase("spool", [&] {
            m_progress.start("spool", static_cast<std::int64_t>(2 * meta.spooled));
            run.plan(meta, [&](std::uint64_t done, std::uint64_t) { m_progress.update(static_cast<std::int64_t>(done)); });
            m_progress.finish();
        });
        phase("snap", [&] {
            std::uint64_t total = 0;
            for (std::size_t g : run.missing()) {
                for (std::size_t leaf : run.groups().leaves[g]) {
                    total += run.layout().bucket_vertices[leaf];
                }
            }
            m_progress.start("snap", static_cast<std::int64_t>(total));
            run.snap(on_tiles);
            m_progress.finish();
        });
        phase("stitch", [&] {
            m_progress.start("stitch", -1);
            run.stitch(on_tiles);
            m_progress.finish();
        });
    } catch (const stitch::budget_error& e) {
        too_small(e);
    } catch (const std::invalid_argument& e) { // options the data made unusable (a tile size too small for the extent)
        throw argument_error(e.what());
    }
}

RunResult Pipeline::run()
{
    ReadSummary read_summary;
    phase("plan", [&] { read_summary = read(); });
    m_result.input = read_summary.records;
    m_result.rejected = read_summary.rejected;
    m_result.input_vertices = read_summary.input_vertices;
    m_result.snapped = read_summary.meta.spooled;
    m_result.fids_renumbered = !read_summary.meta.fids_unique;
    m_result.problems = std::move(read_summary.problems);
    m_result.seconds_read = m_result.phases.back().seconds;
    check_disk(read_summary.meta);
    // The output is created now, before any snapping: a layer or field the driver refuses stops
    // the run before the long part.
    m_plan.write.renumber = m_result.fids_renumbered;
    LayerWriter writer(m_plan.write, *m_plan.layer);
    stitch::ScheduleOptions schedule;
    schedule.threads = m_plan.tiling.threads;
    schedule.model = m_model;
    schedule.memory_pool = m_result.memory_pool = memory_pool();
    schedule.check_cancel = [this] { m_interrupt.check(); };
    stitch::TiledRun run(m_work.store(), m_plan.options, m_plan.tiling, schedule);
    const auto snap_start = Clock::now();
    snap_tiles(run, read_summary.meta);
    m_result.seconds_snap = since(snap_start);
    phase("write", [&] {
        const std::unique_ptr<stitch::OutputMerger> merger = run.output();
        write_layer(m_plan, m_work.store(), *merger, writer, m_result, m_progress, m_interrupt);
        m_result.stats = merger->counts().stats;
        m_result.tiles = merger->tiles();
        m_result.stitch = run.stats();
        m_result.stitch.copied_features = merger->counts().copied;
        m_result.stitch.assembled_features = merger->counts().assembled;
        for (const stitch::TileReport& t : m_result.tiles) {
            m_result.stitch.halo_growths += static_cast<std::size_t>(t.growths);
            m_result.stitch.unbounded_cascades += t.cascade_unbounded ? 1 : 0;
        }
    });
    m_result.seconds_write = m_result.phases.back().seconds;
    std::stable_sort(m_result.problems.begin(), m_result.problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
    return std::move(m_result);
}

nlohmann::json input_files(const Plan& plan)
{
    nlohmann::json files = nlohmann::json::array();
    char** list = plan.dataset->GetFileList();
    for (char** f = list; f && *f; ++f) {
        std::error_code ec;
        const std::filesystem::path p = std::filesystem::weakly_canonical(*f, ec);
        const auto size = std::filesystem::file_size(p, ec);
        const auto time = std::filesystem::last_write_time(p, ec).time_since_epoch().count();
        files.push_back({{"path", p.string()}, {"size", ec ? 0 : size}, {"mtime", static_cast<std::int64_t>(time)}});
    }
    CSLDestroy(list);
    return files;
}

} // namespace

RunResult run_pipeline(Plan& plan, WorkDir& work, const RunBudget& budget, Progress& progress)
{
    return Pipeline(plan, work, budget, progress).run();
}

RunResult snap_run(const SnapArgs& args, const Config& config, Progress& progress, Plan& plan, const StageOutputs& stage)
{
    if (args.input.empty() || args.output.empty()) {
        throw argument_error(std::string("missing ") + (args.input.empty() ? "IN" : "OUT") + ": trisnap snap IN OUT --tolerance T");
    }
    const RunBudget budget = choose_budget(args, config);
    WorkDir work = budget.on_disk ? WorkDir::on_disk(budget.work_dir, budget.resume) : WorkDir::in_memory();
    apply_gdal_budget(budget);
    const auto start = Clock::now();
    plan = make_plan(args, config);
    if (work.on_disk()) {
        plan.write.protected_files.refuse_tree(work.path(), "--work-dir");
    }
    work.bind(run_manifest(plan));
    const double open = since(start);
    CommitGroup outputs; // OUT and the report go into place together, or neither
    plan.write.commit_group = &outputs;
    RunResult result = run_pipeline(plan, work, budget, progress);
    result.seconds_open = open;
    if (stage) {
        stage(outputs, plan, result);
    }
    outputs.commit();
    plan.write.commit_group = nullptr;
    work.finish();
    return result;
}

// Everything that changes the output, and the input's files as they are now: a work directory
// is continued only by the very same run.
std::string run_manifest(const Plan& plan)
{
    const SnapOptions& o = plan.options;
    const stitch::TilingOptions& t = plan.tiling;
    nlohmann::ordered_json m = {
        {"tool", "trisnap"},
        {"version", k_version},
        {"input", {{"path", plan.input_path}, {"files", input_files(plan)}, {"layer", plan.layer->GetName()},
                   {"where", plan.layer->GetAttrQueryString() ? plan.layer->GetAttrQueryString() : ""},
                   {"bbox", plan.bbox}}},
        {"snap", {{"tolerance", fmt::format("{:a}", o.tolerance)}, {"edge_separation", o.edge_separation},
                  {"sliver_factor", o.sliver_factor}, {"grid", o.grid}, {"max_drift_factor", o.max_drift_factor},
                  {"max_operations", o.max_operations}}},
        {"tiling", {{"single", t.plan.single}, {"size", t.plan.tile_size}, {"vertex_budget", t.plan.vertex_budget},
                    {"halo", t.halo_factor}, {"max_growth", t.max_growth}}},
    };
    return m.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

} // namespace trisnap
