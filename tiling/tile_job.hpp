#pragma once
// One tile run: snap what the tile sees (its features cut to its box R = core + halo, grown to
// hold both ends of every edge meeting core + halo, plus the halo: a long edge moves with its
// far end) with evidence reported only in its core, and, when asked, check that no chain of
// snapping reached from the edge of what the tile can see (near the border of R, or beyond)
// into its core. If one did, the core may differ from an untiled run: the halo doubles and the
// tile runs again with the input gathered for the wider halo (up to `max_growth` times; after
// that the outcome says so and the stitch still checks the seams).
#include "core/snap.hpp"
#include "tiling/plan.hpp"
#include "tiling/records.hpp"

#include <functional>
#include <vector>

namespace trisnap::tiling {

/// What a tile snaps: its features (in input order) and its box R.
struct TileJobInput {
    std::vector<TileFeature> features;
    Box reach;
    std::size_t vertices = 0; ///< engine vertices
};

/// The input of the tile for a halo width (layer units).
using Gather = std::function<TileJobInput(double halo)>;

struct TileOutcome {
    double halo = 0;          ///< halo finally used
    int growths = 0;          ///< times the halo doubled
    bool cascade_unbounded = false; ///< still reaching the core at the last growth
    double cascade_x = 0, cascade_y = 0; ///< where a cascade reached the core (first growth)
    std::int64_t cascade_feature = 0;
    std::vector<std::uint64_t> ranks; ///< rank of each input (and output) feature
    std::vector<bool> intact;         ///< each given whole
    std::size_t input_vertices = 0;
    SnapResult result;
    double seconds = 0;
};

struct TileJob {
    Box core;             ///< finite box of the tile's core(s) (clipped to the data extent)
    Region report_region; ///< the core as the engine sees it (infinite outer sides)
    double halo = 0;
    int max_growth = 0;   ///< 0: no cascade test (the seam check alone)
};

TileOutcome run_tile(const TileJob& job, const SnapOptions& options, const Gather& gather);

} // namespace trisnap::tiling
