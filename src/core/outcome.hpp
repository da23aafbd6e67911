#pragma once
// The per-feature outcome problems (collapsed, parts or holes lost or gained, drift), from the
// cleaned input's outline and the output geometry. The engine calls it per feature; the tile stitcher
// calls it on each stitched feature, so both word and place them the same way.
#include "core/input_cleaning.hpp"
#include "core/snap.hpp"

#include <vector>

namespace trisnap::detail {

/// Appends 201/202 (collapsed), 203, 204, 208 and 206 for one feature; returns true when the
/// feature collapsed entirely. `moved` is its max_displacement.
bool outcome_problems(const Outline& cf, const Geometry& g, double moved, const SnapOptions& options,
                      std::vector<Problem>& problems);

} // namespace trisnap::detail
