#pragma once
// What one tile snaps: every input edge that meets the tile's box R (core + halo), whole and
// with its exact input coordinates, so that a tile and its neighbours see the same segments.
// Rings are closed again outside R: each run of edges that misses R is replaced by a shortcut
// or by a detour along a frame B around everything kept, chosen to go round R the same number
// of times as the run did, so the odd-even membership of every point of R is unchanged. A
// ring that misses R but encloses it becomes its bounding box. Lines keep their runs of edges
// that meet R as separate parts.
#include "core/input_cleaning.hpp"
#include "tiling/plan.hpp"

#include <vector>

namespace trisnap::tiling {

struct TileInput {
    std::vector<Feature> features;   ///< engine input; ids are the input ids
    std::vector<std::size_t> source; ///< index into the cleaned features of each
    std::vector<bool> intact;        ///< given whole (no edge dropped, no detour)
    std::size_t vertices = 0;
};

bool segment_meets_box(const Coord& p, const Coord& q, const Box& b);

/// `candidates`: cleaned features whose box meets R (ascending indices); rejected ones skipped.
/// `has_z[i]`: whether cleaned feature i carries Z.
TileInput build_tile_input(const std::vector<detail::CleanFeature>& clean, const std::vector<bool>& has_z,
                           const std::vector<std::size_t>& candidates, const Box& R);

} // namespace trisnap::tiling
