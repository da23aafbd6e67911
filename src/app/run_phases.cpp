#include "app/run_phases.hpp"

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

// The spool needs about features.bin again for the buckets and as much for the results.
void check_disk(const WorkDir& work, const tiling::WorkStore& store, const stitch::SpoolMeta& meta)
{
    if (!work.on_disk()) {
        return;
    }
    const std::uint64_t features = store.total_bytes();
    const std::uint64_t need = 2 * features + 64 * k_mib;
    const std::uint64_t free = store.free_space();
    if (free < need) {
        throw io_error(work.path(), "", fmt::format("not enough free disk for the work files: about {} more are needed "
                                                    "for {} features, {} are free; give --work-dir on a larger disk",
                                                    format_size(need), meta.spooled, format_size(free)));
    }
}

} // namespace

RunPhases::RunPhases(WorkDir& work, const RunBudget& budget, Progress& progress, const SnapOptions& options,
                     const stitch::TilingOptions& tiling)
    : m_work(work), m_budget(budget), m_progress(progress), m_options(options), m_tiling(tiling)
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
    m_interrupt.set_activity(activity_of(name));
    m_interrupt.check();
    body();
    m_result.phases.push_back(PhaseRecord{name, since(start), peak_rss()});
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

// With a limit, the plan's sample and the FID check's buffer take a sixteenth of it each;
// without, the sample holds up to 16 M vertices (256 MiB).
void RunPhases::read(Plan& plan)
{
    ReadSummary summary;
    phase("plan", [&] {
        if (m_work.resumed() && trisnap::load_read(m_work.store(), summary)) {
            spdlog::info("read: taken from the work directory (resumed)");
            return;
        }
        const std::uint64_t limit = m_budget.memory_limit;
        const std::size_t sample_cap = limit ? static_cast<std::size_t>(limit / 16 / 16) : std::size_t{16} << 20;
        const std::size_t fid_buffer = limit ? static_cast<std::size_t>(limit / 16 / 8) : std::numeric_limits<std::size_t>::max();
        summary = read_layer(plan, m_work.store(), sample_cap, fid_buffer, m_progress, m_interrupt);
    });
    m_result.seconds_read = m_result.phases.back().seconds;
    take_read(summary);
    check_disk(m_work, m_work.store(), m_meta);
}

bool RunPhases::load_read()
{
    ReadSummary summary;
    if (!trisnap::load_read(m_work.store(), summary)) {
        return false;
    }
    take_read(summary);
    if (m_work.store().exists(stitch::files::layout)) {
        // The sample's vertices serve only the tile plan, which is made (up to 256 MiB).
        m_meta.sample.xs = {};
        m_meta.sample.ys = {};
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
void RunPhases::too_small(const stitch::budget_error& e) const
{
    const std::uint64_t held = current_rss() + reserved_margin(m_budget);
    const std::uint64_t need = held + m_model.tile_bytes(e.vertices());
    throw argument_error(fmt::format("--memory-limit {} is too small: {}; the smallest limit that would work is about {}",
                                     format_size(m_budget.memory_limit), e.what(), format_size(need + need / 8)));
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
    auto on_pass = [&](std::uint64_t done, std::uint64_t) { m_progress.update(static_cast<std::int64_t>(done / 2)); };
    phase("spool", [&] {
        m_progress.start("spool", static_cast<std::int64_t>(m_meta.spooled), "features");
        guarded([&] { m_run->plan(m_meta, on_pass); });
        m_progress.finish();
    });
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
}

void RunPhases::stitch()
{
    // Only tiles merged at a seam are snapped again; their vertices are known when the check finds them.
    auto on_tiles = [&](std::uint64_t done, std::uint64_t total) {
        m_progress.update(static_cast<std::int64_t>(done), static_cast<std::int64_t>(total));
    };
    phase("stitch", [&] {
        m_progress.start("stitch", -1, "vertices snapped again");
        guarded([&] { m_run->stitch(on_tiles); });
        m_progress.finish();
    });
}

void RunPhases::write(Plan& plan, LayerWriter& writer)
{
    phase("write", [&] {
        const std::unique_ptr<stitch::OutputMerger> merger = m_run->output();
        write_layer(plan, m_work.store(), *merger, writer, m_result, m_progress, m_interrupt);
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
    std::stable_sort(m_result.problems.begin(), m_result.problems.end(), [](const Problem& a, const Problem& b) {
        return std::tie(a.layer, a.feature_id, a.code) < std::tie(b.layer, b.feature_id, b.code);
    });
    return std::move(m_result);
}

} // namespace trisnap
