#pragma once
// The seam check: for every tile, the edges it produced within the seam band of another tile's
// core must be exactly the edges the stitched layer holds there (the edges owned, each by the
// tile whose core holds its midpoint). Where they differ, the tiles are merged and snapped again
// as one. When no seam disagrees, every vertex of the stitched layer has exactly the
// neighbourhood one tile computed, so the contract that holds in every tile holds in the
// stitched layer (stitch/README.md). Reads only seams-<group> files, a tile and its neighbours
// at a time.
#include "core/problems.hpp"
#include "stitch/layout.hpp"
#include "tiling/work_store.hpp"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace trisnap::stitch {

struct SeamVerdict {
    std::vector<std::pair<std::size_t, std::size_t>> pairs; ///< groups to merge (a < b), sorted
    /// Problem 301 per disagreeing tile, keyed by the rank of a feature on the seam (the
    /// feature_id is filled in when features get their FIDs).
    std::vector<std::pair<std::uint64_t, Problem>> problems;
};

/// Called with (passes done, of all): each tile is read in two passes (which tiles its seam
/// edges come near, then its own check), so `of` is twice the tiles; from worker threads, one
/// call at a time, never going back.
using SeamProgress = std::function<void(std::uint64_t, std::uint64_t)>;

/// `dropped`: ranks of the features failed tiles dropped (--on-error skip), ascending; their edges
/// are in no output, so they are left out of the comparison.
SeamVerdict check_seams(const tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, int threads,
                        const std::vector<std::uint64_t>& dropped = {}, const SeamProgress& progress = {});

/// Merges the groups of every pair (transitively) into new groups, which start from the widest
/// halo of their parts; their old files are removed. Returns the new groups, ascending.
std::vector<std::size_t> merge_groups(tiling::WorkStore& store, Groups& groups,
                                      const std::vector<std::pair<std::size_t, std::size_t>>& pairs);

} // namespace trisnap::stitch
