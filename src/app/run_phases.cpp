#include "app/run_phases.hpp"

#include "app/command.hpp"
#include "app/disk_space.hpp"
#include "app/memory.hpp"
#include "config/errors.hpp"
#include "io/io_error.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <string_view>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::uint64_t k_mib = 1024 * 1024;

double since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

} // namespace

RunPhases::RunPhases(WorkDir& work, const RunBudget& budget, Progress& progress, InterruptGuard& interrupt,
                     const SnapOptions& options, const stitch::TilingOptions& tiling)
    : m_work(work), m_budget(budget), m_progress(progress), m_options(options), m_tiling(tiling), m_interrupt(interrupt)
{
    m_result.budget = budget;
    m_result.resumed = work.resumed();
    m_result.tiled = !tiling.plan.single;
}

RunPhases::~RunPhases() = default;

/// "snapping" for the phase "snap": what an interrupted run says it was doing.
static const char* activity_of(std::string_view phase)
{
    if (phase == "plan") {
        return "reading";
    }
    if (phase == "spool") {
        return "spooling";
    }
    if (phase == "snap") {
        return "snapping";
    }
    if (phase == "stitch") {
        return "stitching";
    }
    return "writing";
}

template <class F>
void RunPhases::phase(const char* name, F&& body)
{
    const auto start = Clock::now();
    const double cpu = process_cpu_seconds();
    m_interrupt.set_activity(activity_of(name));
    m_interrupt.check();
    body();
    // A signal the phase's own checks did not see (the spool and the seam check have none
    // between their passes) is named after this phase, not the next.
    m_interrupt.check_at(name);
    m_result.phases.push_back(PhaseRecord{name, since(start), peak_rss(), process_cpu_seconds() - cpu});
    m_result.spool_bytes = std::max(m_result.spool_bytes, m_work.bytes());
    spdlog::info("{}: {:.2f} s, peak memory {}, work files {}", name, m_result.phases.back().seconds,
                 format_size(peak_rss()), format_size(m_work.bytes()));
}

// The tiled run's own errors, in the terms of the command line.
template <class F>
void RunPhases::guarded(F&& body) const
{
    try {
        body();
    } catch (const stitch::budget_error& e) {
        too_small(e);
    } catch (const std::invalid_argument& e) { // options the data made unusable (a tile size too small for the extent)
        throw argument_error(e.what());
    }
}

void RunPhases::take_read(ReadSummary& summary)
{
    m_result.input = summary.records;
    m_result.rejected = summary.rejected;
    m_result.input_vertices = summary.input_vertices;
    m_result.snapped = summary.meta.spooled;
    m_result.fids_renumbered = false;
    m_result.layers.clear();
    for (const LayerRead& l : summary.layers) {
        LayerCounts& c = m_result.layers.emplace_back();
        c.input = l.records;
        c.rejected = l.rejected;
        c.snapped = l.snapped;
        c.input_vertices = l.input_vertices;
        c.fids_renumbered = !l.fids_unique;
        m_result.fids_renumbered = m_result.fids_renumbered || c.fids_renumbered;
    }
    m_result.problems = std::move(summary.problems);
    m_meta = std::move(summary.meta);
}

// With a limit, the plan's sample and the FID check's buffer take a sixteenth of it each, the
// problems a thirty-second; without, the sample holds up to 16 M vertices (256 MiB).
void RunPhases::read(Plan& plan)
{
    ReadSummary summary;
    phase("plan", [&] {
        if (m_work.resumed() && trisnap::load_read(m_work.store(), problem_buffer(), summary)) {
            spdlog::info("read: taken from the work directory (resumed)");
            return;
        }
        check_disk_before_read(m_work, plan);
        const std::uint64_t limit = m_budget.memory_limit;
        const ReadBuffers buffers{sample_vertices(limit), fid_buffer(limit), problem_buffer(),
                                  limit == 0 || limit >= 512 * k_mib};
        summary = read_layer(plan, m_work.store(), buffers, m_progress, m_interrupt);
    });
    m_result.seconds_read = m_result.phases.back().seconds;
    take_read(summary);
    check_disk_after_read(m_work, m_meta);
}

bool RunPhases::load_read()
{
    ReadSummary summary;
    if (!trisnap::load_read(m_work.store(), problem_buffer(), summary)) {
        return false;
    }
    take_read(summary);
    if (m_work.store().exists(stitch::files::layout)) {
        // The sample's vertices serve only the tile plan, which is made (up to 256 MiB).
        m_meta.sample.drop_sample();
    }
    return true;
}

// What the tiles in flight may take: the limit less what the process holds now and the margin
// for GDAL's caches and the buffers.
std::uint64_t RunPhases::memory_pool() const
{
    if (m_budget.memory_limit == 0) {
        return 0;
    }
    const std::uint64_t rss = current_rss();
    const std::uint64_t held = rss + reserved_margin(m_budget);
    const std::uint64_t least = m_model.tile_bytes(1000);
    if (m_budget.memory_limit < held + least) {
        throw argument_error(fmt::format("--memory-limit {} is too small: the process holds {} before any tile, and the "
                                         "smallest tile needs {}; the smallest limit that would work is about {}",
                                         format_size(m_budget.memory_limit), format_size(held), format_size(least),
                                         smallest_limit_text(rss, m_model.tile_bytes(20000))));
    }
    return m_budget.memory_limit - held;
}

// The limit under which a fresh run of this layer would hold `rss` (as now, the buffers that grow
// with the limit grown) beside the margin and `tile`: a whole number of MiB, never less than it.
std::string RunPhases::smallest_limit_text(std::uint64_t rss, std::uint64_t tile) const
{
    const HeldByLimit grows{m_meta.vertices, m_result.input};
    const std::uint64_t limit = smallest_limit(m_budget.memory_limit, rss, grows, tile);
    return fmt::format("{} MiB", limit / k_mib);
}

// The smallest limit under which the tile that did not fit would run alone.
void RunPhases::too_small(const stitch::budget_error& e) const
{
    throw argument_error(fmt::format("--memory-limit {} is too small: {}; the smallest limit that would work is about {}",
                                     format_size(m_budget.memory_limit), e.what(),
                                     smallest_limit_text(current_rss(), m_model.tile_bytes(e.vertices()))));
}

void RunPhases::open_tiles()
{
    stitch::ScheduleOptions schedule;
    schedule.threads = m_tiling.threads;
    schedule.model = m_model;
    schedule.memory_pool = m_result.memory_pool = memory_pool();
    schedule.check_cancel = [this] { m_interrupt.check(); };
    m_run = std::make_unique<stitch::TiledRun>(m_work.store(), m_options, m_tiling, schedule);
}

void RunPhases::spool()
{
    // Two passes over the features (reach boxes, buckets): counted as features, each pass half of one.
    auto on_pass = [&](std::uint64_t done, std::uint64_t) {
        m_interrupt.check(); // every 4096 features of each pass
        m_progress.update(static_cast<std::int64_t>(done / 2));
    };
    phase("spool", [&] {
        m_progress.start("spool", static_cast<std::int64_t>(m_meta.spooled), "features");
        guarded([&] { m_run->plan(m_meta, on_pass); }); // takes the sample's vertices (up to limit/16 bytes)
        m_progress.finish();
    });
    // Said once the tiles are snapped: a run that stops on a tile too large for the limit says
    // only that, in one line. A resumed run's plan was made before (from another pool): nothing.
    const std::uint64_t wanted = m_tiling.plan.vertex_budget;
    const std::uint64_t planned = m_run->planned_vertex_budget();
    if (planned > 0 && planned < wanted) {
        const auto threads = static_cast<std::uint64_t>(m_run->threads());
        m_small_tiles = fmt::format("--memory-limit {} left {} for tiles: tiles of at most {} vertices instead of {} "
                                    "(--tile-vertex-budget), a slower run; about {} would give full-size tiles",
                                    format_size(m_budget.memory_limit), format_size(m_result.memory_pool), planned, wanted,
                                    smallest_limit_text(current_rss(), m_model.tile_bytes(wanted) * threads));
    }
}

void RunPhases::snap(const std::function<bool(std::size_t)>& mine)
{
    auto on_tiles = [&](std::uint64_t done, std::uint64_t) { m_progress.update(static_cast<std::int64_t>(done)); };
    phase("snap", [&] {
        std::uint64_t total = 0;
        for (std::size_t g : m_run->missing()) {
            if (mine && !mine(g)) {
                continue;
            }
            for (std::size_t leaf : m_run->groups().leaves[g]) {
                total += m_run->layout().bucket_vertices[leaf];
            }
        }
        m_progress.start("snap", static_cast<std::int64_t>(total), "vertices");
        guarded([&] { m_run->snap(on_tiles, mine); });
        m_progress.finish();
    });
    if (!m_small_tiles.empty()) {
        spdlog::warn("{}", m_small_tiles);
    }
}

void RunPhases::stitch()
{
    auto on_tiles = [&](std::uint64_t done, std::uint64_t total) {
        m_progress.update(static_cast<std::int64_t>(done), static_cast<std::int64_t>(total));
    };
    phase("stitch", [&] {
        m_progress.start("stitch", static_cast<std::int64_t>(m_run->groups().live(m_run->layout()).size()), "tiles");
        guarded([&] { m_run->stitch(on_tiles); });
        m_progress.finish();
    });
}

void RunPhases::write(Plan& plan, LayerWriter& writer)
{
    phase("write", [&] {
        const std::unique_ptr<stitch::OutputMerger> merger = m_run->output();
        write_layer(plan, m_work.store(), *merger, writer, m_result, m_progress, m_interrupt);
        if (writer.output_in_place()) {
            m_interrupt.outputs_in_place(); // streamed, or its transaction committed: nothing takes it back
        }
        m_result.stats = merger->counts().stats;
        m_result.tiles = merger->tiles();
        m_result.stitch = m_run->stats();
        m_result.stitch.copied_features = merger->counts().copied;
        m_result.stitch.assembled_features = merger->counts().assembled;
        m_result.stitch.failed_features = merger->counts().failed;
        m_result.stitch.tiles_dropped = 0;
        for (const stitch::TileReport& t : m_result.tiles) {
            m_result.stitch.halo_growths += static_cast<std::size_t>(t.growths);
            m_result.stitch.unbounded_cascades += t.cascade_unbounded ? 1 : 0;
            m_result.stitch.tiles_dropped += t.failed ? 1 : 0;
        }
    });
    m_result.seconds_write = m_result.phases.back().seconds;
}

void RunPhases::set_interrupt_message(const char* message)
{
    m_interrupt.set_message(message);
}

stitch::TiledRun& RunPhases::tiles() { return *m_run; }

RunResult& RunPhases::result() { return m_result; }

RunResult RunPhases::finish()
{
    m_result.problems.seal();
    spdlog::info("problems: {}, in {} sorted runs of the work files", m_result.problems.size(),
                 m_result.problems.runs().size());
    return std::move(m_result);
}

// Problems held in memory before they go to the store: a thirty-second of the limit (a problem
// takes about 100 bytes: 2 GiB holds 640 k at once); without a limit, all of them.
std::size_t RunPhases::problem_buffer() const
{
    return m_budget.memory_limit ? static_cast<std::size_t>(m_budget.memory_limit / 32)
                                 : std::numeric_limits<std::size_t>::max();
}

} // namespace trisnap
