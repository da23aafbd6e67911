#pragma once
// Tiled snapping: plan tiles (tiling/plan), snap each with a halo in parallel (tiling/tile_job),
// then stitch. Every output edge is owned by the tile whose half-open core holds its midpoint.
// Seam check: along every seam, the edges each tile produced within 2t of the seam must be the
// very edges the stitched layer holds there. Where they differ, the tiles on both sides are
// merged into one and snapped again (problem 301), until no seam disagrees; then each vertex of
// the stitched layer has exactly the neighbourhood one tile produced, so the contract that
// holds in every tile holds in the stitched layer. A feature owned by one tile that had it whole
// is copied; a feature cut by seams is rebuilt from its owned edges (core/assemble.hpp).
#include "core/snap.hpp"
#include "tiling/plan.hpp"

#include <functional>
#include <string>
#include <vector>

namespace trisnap::stitch {

struct TilingOptions {
    tiling::PlanOptions plan;
    /// Halo width as a factor of t. Cascades of snaps were seen to reach 9t (Monaco, 1e-6 deg)
    /// and 16t (1e-5 deg); a cascade that reaches the core from the halo's border doubles it.
    double halo_factor = 32;
    /// How many times a tile's halo may double when the cascade test fires (0: no test). The
    /// test is conservative (any chain of moved vertices within 2t links the halo's border to
    /// the core): it fired on 2 of Monaco's 4 tiles at 1e-6 deg and doubled their cost, while
    /// tiled output without it was 100 % identical to untiled on every layer measured (halo 4t
    /// to 32t). So it is off by default; the seam check keeps the layer consistent either way.
    int max_growth = 0;
    /// Threads for tiles (0: all cores). The output does not depend on it.
    int threads = 0;
};

/// One executed tile (after seam merges: one or more plan leaves).
struct TileReport {
    std::size_t id = 0;              ///< smallest plan leaf in it
    std::size_t leaves = 1;          ///< plan leaves merged into it
    tiling::Box core;                ///< finite box of its core(s)
    double halo = 0;                 ///< final halo width (layer units)
    int growths = 0;                 ///< halo doublings (cascades reaching the core)
    std::size_t features = 0;        ///< features given to it (whole or cut)
    std::size_t input_vertices = 0;
    std::size_t output_edges_owned = 0;
    std::size_t problems = 0;        ///< problems it reported in its core
    double seconds = 0;              ///< wall time of its last run
    std::size_t runs = 1;            ///< times snapped (seam merges run a tile again)
};

struct StitchStats {
    std::size_t leaves = 0;          ///< tiles in the plan
    std::size_t tiles = 0;           ///< tiles in the end (after merges)
    std::size_t seam_merges = 0;     ///< tile pairs merged because a seam disagreed
    std::size_t halo_growths = 0;
    std::size_t unbounded_cascades = 0;
    std::size_t copied_features = 0;    ///< taken whole from one tile
    std::size_t assembled_features = 0; ///< rebuilt from edges of several tiles
    std::size_t tile_runs = 0;
    double seconds_tiles = 0;        ///< wall time of the tile runs
    double seconds_stitch = 0;
};

struct TiledResult {
    SnapResult result; ///< as snap() would return it
    std::vector<TileReport> tiles;
    StitchStats stitch;
};

/// Called serially after each tile run: (tiles done, tiles planned in this round).
using TileProgress = std::function<void(std::size_t, std::size_t)>;

/// Throws std::invalid_argument for unusable options (like snap()).
TiledResult snap_tiled(const std::vector<Feature>& features, const SnapOptions& options, const TilingOptions& tiling,
                       const TileProgress& progress = {});

} // namespace trisnap::stitch
