#include "stitch/tiled_snap.hpp"
#include "stitch/tiled_snap_impl.hpp"
#include "stitch/tile_gates.hpp"

#include "stitch/seams.hpp"
#include "stitch/tile_run.hpp"

#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace trisnap::stitch {
namespace {

const std::string k_notes = "notes.bin"; ///< 301s of the seam rounds so far

double seconds_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

void TiledRun::Impl::save_groups()
{
    std::string bytes;
    tiling::ByteWriter w(bytes);
    groups.save(w);
    store.put(k_notes, encode_notes(notes));
    store.put(files::groups, bytes);
}

std::uint64_t pool_tile_vertices(const MemoryModel& model, std::uint64_t pool, int threads, std::uint64_t wanted)
{
    if (pool == 0) {
        return wanted;
    }
    std::uint64_t share = 0;
    for (std::uint64_t k = static_cast<std::uint64_t>(std::max(threads, 1)); k >= 1; --k) {
        share = model.vertices_within(pool / k);
        if (share >= std::min(wanted, k_least_pool_tile_vertices)) {
            break;
        }
    }
    return std::min(wanted, std::max<std::uint64_t>(share, 16));
}

// The largest tile the pool can hold alone (each tile must fit; tiles bigger than a share of
// the pool just run with fewer beside them).
std::uint64_t TiledRun::Impl::max_tile_vertices() const
{
    return schedule.memory_pool == 0 ? 0 : std::max<std::uint64_t>(schedule.model.vertices_within(schedule.memory_pool), 1);
}

// Biggest first (the last to finish are small); at most 2 x threads in the pipeline and, with
// a pool, only as many running as their estimates fit. Results do not depend on the order.
// A tile whose engine throws stops the run (tile_error), or with OnError::skip is retried merged
// with its neighbours (`retry`), then untiled in its region, and when that fails too, committed
// as failed.
void TiledRun::Impl::run_groups(std::vector<std::size_t> pending, const TileProgress& progress, bool retry)
{
    const std::vector<std::pair<std::size_t, std::string>> failed = run_once(std::move(pending), progress);
    if (failed.empty()) {
        return;
    }
    if (retry) {
        stats.tiles_failed += failed.size();
        retry_merged(failed, progress);
        return;
    }
    retry_whole(failed, "alone");
}

// Runs the groups; returns the ones that failed (OnError::skip) with the engine's message, in
// group order, with nothing of them committed.
std::vector<std::pair<std::size_t, std::string>> TiledRun::Impl::run_once(std::vector<std::size_t> pending,
                                                                         const TileProgress& progress)
{
    // A plan of one leaf in memory that stops on a failure and never grows its halo reads its
    // features whole once: the spool keeps only their outlines after that (the stitch's need).
    const bool cut_spool = !store.on_disk() && whole_spool_bucket(layout) && tiling.on_error == OnError::stop &&
                           tiling.max_growth == 0;
    const TileRunner runner(store, layout, groups, meta, options, tiling.max_growth, cut_spool);
    std::vector<std::pair<std::uint64_t, std::size_t>> order;
    std::uint64_t total = 0;
    for (std::size_t g : pending) {
        order.emplace_back(runner.vertices(g), g);
        total += runner.vertices(g);
    }
    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    if (schedule.memory_pool > 0) {
        for (const auto& [n, g] : order) {
            if (schedule.model.tile_bytes(n) > schedule.memory_pool) {
                throw budget_error("tile " + std::to_string(groups.leaves[g].front()) + " (" + std::to_string(groups.leaves[g].size()) +
                                       " leaves merged at a seam) needs " + std::to_string(n) + " vertices in one triangulation",
                                   n);
            }
        }
    }
    MemoryGate gate(schedule.memory_pool);
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t next = 0;
    LiveCount live(progress, total);
    std::vector<std::uint64_t> shares(order.size(), 0);
    std::vector<std::string> failures(order.size()); // "" or the engine's message, by position in `order`
    tbb::task_arena arena(threads());
    arena.execute([&] {
        tbb::parallel_pipeline(
            static_cast<std::size_t>(2 * threads()),
            tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                                [&](tbb::flow_control& fc) -> std::size_t {
                                                    if (schedule.check_cancel) {
                                                        schedule.check_cancel();
                                                    }
                                                    if (next >= order.size()) {
                                                        fc.stop();
                                                        return 0;
                                                    }
                                                    return next++;
                                                }) &
                tbb::make_filter<std::size_t, std::size_t>(tbb::filter_mode::parallel,
                                                           [&](std::size_t k) {
                                                               const std::uint64_t bytes = schedule.model.tile_bytes(order[k].first);
                                                               gate.acquire(bytes);
                                                               struct Release {
                                                                   MemoryGate& gate;
                                                                   std::uint64_t bytes;
                                                                   ~Release() { gate.release(bytes); }
                                                               } release{gate, bytes};
                                                               failures[k] = run_one(runner, order[k].second, [&, k](std::size_t done, std::size_t of) {
                                                                   live.running(shares[k], order[k].first, done, of);
                                                               });
                                                               return k;
                                                           }) &
                tbb::make_filter<std::size_t, void>(tbb::filter_mode::serial_in_order, [&](std::size_t k) {
                    ++groups.runs[order[k].second];
                    if (failures[k].empty()) {
                        ++stats.tile_runs;
                    }
                    live.finished(shares[k], order[k].first);
                }));
    });
    stats.seconds_tiles += seconds_since(t0);
    std::vector<std::pair<std::size_t, std::string>> failed; // group, reason; in group order
    for (std::size_t k = 0; k < order.size(); ++k) {
        if (!failures[k].empty()) {
            failed.emplace_back(order[k].second, failures[k]);
        }
    }
    std::sort(failed.begin(), failed.end());
    return failed;
}

// Runs one tile; returns "" or, with OnError::skip, what the engine threw. A cancel (thrown by
// check_cancel from the engine's progress), running out of memory, a budget error and a work
// file that cannot be read or written (a full disk) always leave the run: they are not the
// tile's fault, and retrying it would write more.
std::string TiledRun::Impl::run_one(const TileRunner& runner, std::size_t group, const std::function<void(std::size_t, std::size_t)>& on_progress,
                                    TileInputMode mode)
{
    bool cancelled = false;
    const std::uint64_t cap = mode == TileInputMode::whole ? max_tile_vertices() : 0;
    try {
        runner.run(group, [&](std::size_t done, std::size_t of) {
            if (schedule.check_cancel) {
                try {
                    schedule.check_cancel();
                } catch (...) {
                    cancelled = true;
                    throw;
                }
            }
            on_progress(done, of);
        }, mode, cap);
        return {};
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const budget_error&) {
        throw;
    } catch (const tiling::work_error&) {
        throw;
    } catch (const std::exception& e) {
        if (cancelled) {
            throw;
        }
        const std::string reason = *e.what() ? e.what() : "an exception without a message";
        if (tiling.on_error == OnError::stop) {
            const tiling::Box core = group_core(layout, groups, group);
            char box[200];
            std::snprintf(box, sizeof box, "%.17g,%.17g,%.17g,%.17g", core.xmin, core.ymin, core.xmax, core.ymax);
            throw tile_error(groups.leaves[group].front(),
                             "tile " + std::to_string(groups.leaves[group].front()) + " (core " + box + ", " +
                                 std::to_string(runner.vertices(group)) + " vertices, " +
                                 runner.describe_features(group) + ") failed: " + reason);
        }
        return reason;
    }
}

TiledRun::TiledRun(tiling::WorkStore& store, const SnapOptions& options, const TilingOptions& tiling,
                   const ScheduleOptions& schedule)
    : m_impl(std::make_unique<Impl>(store, options, tiling, schedule))
{
}

TiledRun::~TiledRun() = default;

void TiledRun::plan(SpoolMeta& meta, const PassProgress& progress)
{
    Impl& m = *m_impl;
    tiling::PlanInput sample = meta.sample.take_vertices();
    m.meta = meta; // without the sample's vertices: their one copy goes to the plan
    if (m.store.exists(files::layout) && m.store.exists(files::groups)) {
        const std::string layout = m.store.get(files::layout);
        tiling::ByteReader lr(layout, "layout");
        m.layout = TileLayout::load(lr);
        const std::string groups = m.store.get(files::groups);
        tiling::ByteReader gr(groups, "groups");
        m.groups = Groups::load(gr);
        m.notes = decode_notes(m.store.get(k_notes));
        return;
    }
    TilingOptions tiling = m.tiling;
    BucketOptions bo;
    bo.halo = tiling.halo_factor * m.options.tolerance;
    bo.seam_band = 2 * m.options.tolerance + 4 * m.options.grid;
    bo.max_tile_vertices = m.max_tile_vertices();
    bo.threads = m.threads();
    if (m.schedule.memory_pool > 0) {
        tiling.plan.vertex_budget = static_cast<std::size_t>(
            pool_tile_vertices(m.schedule.model, m.schedule.memory_pool, m.threads(), tiling.plan.vertex_budget));
        bo.buffer_bytes = static_cast<std::size_t>(std::clamp<std::uint64_t>(m.schedule.memory_pool / 8, 1u << 20, 64u << 20));
    }
    m.planned_budget = tiling.plan.vertex_budget;
    m.layout = make_buckets(m.store, m.meta, std::move(sample), tiling, bo, progress);
    m.groups = Groups::of_layout(m.layout);
    m.save_groups();
}

std::vector<std::size_t> TiledRun::missing() const
{
    std::vector<std::size_t> out;
    for (std::size_t g : m_impl->groups.live(m_impl->layout)) {
        if (!m_impl->store.exists(files::result(g)) || !m_impl->store.exists(files::seams(g))) {
            out.push_back(g);
        }
    }
    return out;
}

void TiledRun::snap(const TileProgress& progress, const std::function<bool(std::size_t)>& mine)
{
    std::vector<std::size_t> pending;
    for (std::size_t g : missing()) {
        if (!mine || mine(g)) {
            pending.push_back(g);
        }
    }
    // A shard (`mine`) shares the groups file with other processes: it cannot merge a failed
    // tile with neighbours it does not own, so with OnError::skip its failed tiles are committed
    // as failed at once (the stitch's seam loop may still merge them later).
    m_impl->run_groups(std::move(pending), progress, !mine);
}

// Progress in tiles: each round checks every live tile (two passes each), then snaps the merged
// ones again; a round that merges adds them and the next round's checks to the total.
void TiledRun::stitch(const TileProgress& progress)
{
    Impl& m = *m_impl;
    std::uint64_t base = 0; // tiles checked or snapped again in the rounds before
    auto report = [&](std::uint64_t done, std::uint64_t total) {
        if (progress) {
            progress(done, total);
        }
    };
    for (;;) {
        const std::uint64_t live = m.groups.live(m.layout).size();
        report(base, base + live);
        const auto t0 = std::chrono::steady_clock::now();
        const SeamVerdict verdict = check_seams(m.store, m.layout, m.groups, m.threads(), m.dropped_ranks(),
                                                [&](std::uint64_t passes, std::uint64_t of) {
                                                    report(base + passes / 2, base + of / 2);
                                                });
        m.stats.seconds_stitch += seconds_since(t0);
        base += live;
        if (verdict.pairs.empty()) {
            break;
        }
        m.notes.insert(m.notes.end(), verdict.problems.begin(), verdict.problems.end());
        const std::vector<std::size_t> added = merge_groups(m.store, m.groups, verdict.pairs);
        m.save_groups();
        const std::uint64_t rerun = added.size();
        const std::uint64_t total = base + rerun + m.groups.live(m.layout).size();
        m.run_groups(added, [&](std::uint64_t vertices, std::uint64_t of) {
            report(base + (of == 0 ? 0 : vertices * rerun / of), total);
        });
        base += rerun;
    }
    m.save_groups();
}

std::unique_ptr<OutputMerger> TiledRun::output()
{
    Impl& m = *m_impl;
    std::vector<std::pair<std::uint64_t, Problem>> notes = m.notes;
    auto merger = std::make_unique<OutputMerger>(m.store, m.layout, m.groups, m.meta, m.options);
    for (const TileReport& t : merger->tiles()) {
        if (t.growths == 0) {
            continue;
        }
        Problem p;
        p.code = ProblemCode::seam_cascade;
        p.message = "a cascade of snaps reached the tile core from its halo; the halo grew to " +
                    std::to_string(t.halo / m.options.tolerance) + " x tolerance" +
                    (t.cascade_unbounded ? " and the cascade still reached it (left to the seam check)" : "");
        p.x = t.cascade_x;
        p.y = t.cascade_y;
        notes.emplace_back(t.cascade_rank, p);
    }
    merger->set_notes(std::move(notes));
    return merger;
}

const TileLayout& TiledRun::layout() const { return m_impl->layout; }

const Groups& TiledRun::groups() const { return m_impl->groups; }

std::uint64_t TiledRun::planned_vertex_budget() const { return m_impl->planned_budget; }

int TiledRun::threads() const { return m_impl->threads(); }

StitchStats TiledRun::stats() const
{
    StitchStats s = m_impl->stats;
    s.leaves = m_impl->layout.plan.size();
    s.tiles = m_impl->groups.live(m_impl->layout).size();
    s.seam_merges = m_impl->groups.seam_merges;
    return s;
}

std::string validate(const TilingOptions& tiling)
{
    if (!(tiling.halo_factor >= 2) || !std::isfinite(tiling.halo_factor)) {
        return "halo factor must be finite and >= 2, got " + std::to_string(tiling.halo_factor);
    }
    if (tiling.plan.tile_size < 0 || !std::isfinite(tiling.plan.tile_size)) {
        return "tile size must be finite and > 0, got " + std::to_string(tiling.plan.tile_size);
    }
    if (tiling.max_growth < 0) {
        return "max halo growth must be >= 0";
    }
    return {};
}

TiledResult snap_tiled(const std::vector<Feature>& features, const SnapOptions& options, const TilingOptions& tiling,
                       const TileProgress& progress)
{
    if (const std::string msg = validate(options); !msg.empty()) {
        throw std::invalid_argument(msg);
    }
    if (const std::string msg = validate(tiling); !msg.empty()) {
        throw std::invalid_argument(msg);
    }
    const std::unique_ptr<tiling::WorkStore> store = tiling::make_memory_store();
    TiledResult out;
    std::vector<Problem>& problems = out.result.problems;
    FeatureSpool spool(*store, options.tolerance, std::numeric_limits<std::size_t>::max(), std::numeric_limits<std::size_t>::max());
    for (std::size_t i = 0; i < features.size(); ++i) {
        spool.add(i, features[i].id, features[i].geometry, problems);
    }
    SpoolMeta meta = spool.finish();
    ScheduleOptions schedule;
    schedule.threads = tiling.threads;
    TiledRun run(*store, options, tiling, schedule);
    run.plan(meta);
    run.snap(progress);
    run.stitch();
    const std::unique_ptr<OutputMerger> merger = run.output();
    out.result.features.resize(features.size());
    OutputItem item;
    while (merger->next(item)) {
        out.result.features[item.seq] = std::move(item.output);
        problems.insert(problems.end(), std::make_move_iterator(item.problems.begin()),
                        std::make_move_iterator(item.problems.end()));
    }
    std::stable_sort(problems.begin(), problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
    out.result.stats = merger->counts().stats;
    out.tiles = merger->tiles();
    out.stitch = run.stats();
    out.stitch.copied_features = merger->counts().copied;
    out.stitch.assembled_features = merger->counts().assembled;
    out.stitch.failed_features = merger->counts().failed;
    out.stitch.tiles_dropped = 0;
    for (const TileReport& t : out.tiles) {
        out.stitch.halo_growths += static_cast<std::size_t>(t.growths);
        out.stitch.unbounded_cascades += t.cascade_unbounded ? 1 : 0;
        out.stitch.tiles_dropped += t.failed ? 1 : 0;
    }
    return out;
}

} // namespace trisnap::stitch
