#pragma once
// Tiled snapping over a work store (stitch/spool.hpp, tile_run.hpp, seams.hpp, output.hpp):
//  plan    - the tile plan from the spooled sample, reach boxes, buckets (split to the budget);
//  snap    - every tile without a result, in parallel on oneTBB, biggest first, with the tiles in
//            flight bounded by a memory pool (each tile's estimate from its bucket's vertices);
//  stitch  - the seam check; disagreeing tiles are merged and snapped again (problem 301) until
//            every seam agrees: then each vertex of the stitched layer has exactly the
//            neighbourhood one tile produced, so the contract that holds in every tile holds in
//            the stitched layer;
//  output  - the features in input order (OutputMerger).
// Every phase leaves its files committed in the store, so a run can stop after any tile and
// continue (resume, or another machine's shard) with the same result: results depend only on
// the files, never on the order tiles ran in, the threads, or the machine.
// snap_tiled() runs it all in memory on a vector of features (tests, benchmarks).
#include "core/snap.hpp"
#include "stitch/layout.hpp"
#include "stitch/output.hpp"
#include "stitch/spool.hpp"
#include "stitch/tile_result.hpp"
#include "tiling/work_store.hpp"

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace trisnap::stitch {

/// What a tile costs in memory: the engine's bytes per input vertex and a fixed part per tile.
/// Set before issue 11's lean engine, from single tiles' peak RSS. The engine now takes 128-272 B
/// a vertex on the shared layers, but up to ~1,550 in a collapse cascade (a ring of 120,000
/// vertices at t = a tenth of its radius). 1,100 stays: well above every shared layer's figure,
/// still below that cascade's, until the model sees the tolerance's collapse pressure (bench/results/REPORT.md, "Huge pages
/// where the host takes free memory back", its paragraph on memory in a collapse cascade).
struct MemoryModel {
    double bytes_per_vertex = 1100;
    std::uint64_t bytes_per_tile = 8u << 20;
    std::uint64_t tile_bytes(std::uint64_t vertices) const
    {
        return bytes_per_tile + static_cast<std::uint64_t>(bytes_per_vertex * static_cast<double>(vertices));
    }
    /// The most vertices a tile may hold within `bytes`.
    std::uint64_t vertices_within(std::uint64_t bytes) const
    {
        return bytes <= bytes_per_tile ? 0 : static_cast<std::uint64_t>(static_cast<double>(bytes - bytes_per_tile) / bytes_per_vertex);
    }
};

/// Tiles smaller than this are not made to let every thread run one within a memory pool:
/// fewer run at once instead.
constexpr std::uint64_t k_least_pool_tile_vertices = 10000;

/// The most input vertices the tiles may hold under a memory pool of `pool` bytes (0: none)
/// for `threads` threads, at most `wanted` (--tile-vertex-budget): a thread's share of the
/// pool, or where that share holds fewer than k_least_pool_tile_vertices the share of fewer
/// threads (the schedule runs only as many tiles at once as the pool holds), down to the whole
/// pool for one tile; at least 16. A share was all it took before: Andorra x43 under 155 MiB
/// left a pool of ~9 MiB, half of it below the model's 8 MiB a tile, and tiles of 16
/// vertices ran for minutes instead of 3 s.
std::uint64_t pool_tile_vertices(const MemoryModel& model, std::uint64_t pool, int threads, std::uint64_t wanted);

/// A tile failed and the run stops (OnError::stop): names the tile, its core and the reason.
class tile_error : public std::runtime_error {
public:
    tile_error(std::size_t tile, const std::string& what) : std::runtime_error(what), m_tile(tile) {}
    std::size_t tile() const { return m_tile; }

private:
    std::size_t m_tile;
};

struct ScheduleOptions {
    int threads = 0;                   ///< 0: all cores
    std::uint64_t memory_pool = 0;     ///< bytes the tiles in flight may take together; 0: no bound
    MemoryModel model;
    /// Called before each tile and from the engine's progress inside running tiles (from worker
    /// threads); throws to stop the run (e.g. on Ctrl-C): the tiles running stop, nothing of
    /// them is committed, and the exception leaves snap()/stitch().
    std::function<void()> check_cancel;
};

struct StitchStats {
    std::size_t leaves = 0;          ///< tiles in the plan (after splits)
    std::size_t tiles = 0;           ///< tiles in the end (after merges)
    std::size_t seam_merges = 0;     ///< tile pairs merged because a seam disagreed
    std::size_t halo_growths = 0;
    std::size_t unbounded_cascades = 0;
    std::size_t copied_features = 0;    ///< taken whole from one tile
    std::size_t assembled_features = 0; ///< rebuilt from edges of several tiles
    std::size_t tile_runs = 0;       ///< tiles snapped by this process
    std::size_t tiles_failed = 0;    ///< tiles that failed alone (--on-error skip)
    std::size_t tiles_dropped = 0;   ///< tiles that failed merged with their neighbours too
    std::size_t failed_features = 0; ///< features not written because of them (303)
    double seconds_tiles = 0;        ///< wall time of the tile runs
    double seconds_stitch = 0;
};

/// Called serially, never going back: (input vertices done, of all tiles); finished tiles count
/// whole, running ones by the engine's progress scaled to their vertices.
using TileProgress = std::function<void(std::uint64_t, std::uint64_t)>;

class TiledRun {
public:
    TiledRun(tiling::WorkStore& store, const SnapOptions& options, const TilingOptions& tiling,
             const ScheduleOptions& schedule);
    ~TiledRun();
    /// Plans and fills the buckets, unless the store holds a plan already (resume); the tile
    /// budget comes from the memory pool when there is one. Takes the sample's vertices out of
    /// `meta` (the plan is their only reader; its extent and counts stay).
    void plan(SpoolMeta& meta, const PassProgress& progress = {});
    /// The tile vertex budget plan() planned with: TilingOptions' own, or less where the memory
    /// pool holds less (pool_tile_vertices()). 0 when plan() took an earlier run's plan (resume)
    /// or has not run.
    std::uint64_t planned_vertex_budget() const;
    /// The threads the tiles run on (ScheduleOptions::threads, or TBB's default).
    int threads() const;
    /// Snaps every tile that has no result yet; `mine(group)` picks a share of them (then a tile
    /// that fails under OnError::skip is not retried merged with its neighbours).
    void snap(const TileProgress& progress = {}, const std::function<bool(std::size_t)>& mine = {});
    /// Groups (tiles) that have no result yet.
    std::vector<std::size_t> missing() const;
    /// Seam check, merging and snapping again until every seam agrees. `progress` counts tiles:
    /// (tiles checked or snapped again, of the tiles to check and snap again so far); a round
    /// that merges tiles adds them, and the next round's checks, to the total.
    void stitch(const TileProgress& progress = {});
    /// The stitched features in input order (after stitch()).
    std::unique_ptr<OutputMerger> output();
    const TileLayout& layout() const;
    const Groups& groups() const;
    StitchStats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

struct TiledResult {
    SnapResult result; ///< as snap() would return it
    std::vector<TileReport> tiles;
    StitchStats stitch;
};

/// Throws std::invalid_argument for unusable options (like snap()).
TiledResult snap_tiled(const std::vector<Feature>& features, const SnapOptions& options, const TilingOptions& tiling,
                       const TileProgress& progress = {});

/// Checks the tiling options; "" when usable, else a one-line reason.
std::string validate(const TilingOptions& tiling);

} // namespace trisnap::stitch
