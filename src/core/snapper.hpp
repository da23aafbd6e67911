#pragma once
// The fix-point driver: snapping events processed strictly smallest distance first.
//
// Events (d = the distance that triggers them; ties by kind, then vertex ids, which are
// canonical, never addresses):
//   1 face   - a triangle whose three edges are all <= t collapses to its centroid (key: its
//              shortest edge, so it wins over that edge's own merge);
//   2 merge  - two vertices <= t apart, with no constraint between them, merge at the midpoint;
// Centroid and midpoint are weighted by how many vertices each side already stands for, so a
// cluster merged pair by pair lands on the mean of its members instead of drifting towards the
// last-merged one (measured: BGT partition at t = 1 m, max vertex move 3.3 t -> see notes).
//   3 sliver - the apex of a triangle on a constrained base, <= sliver*t from it, moves onto the
//              base (split there);
//   4 edge   - a vertex < e*t from a constrained edge it is not on moves onto it (split).
// Cases 3 and 4 merge instead of moving when the vertex is <= t from an end of the edge: they
// leave that to the merge event, which avoids the ping-pong of two vertices snapping onto each
// other's edges with shrinking distances.
//
// Termination: a merge removes at least one vertex; a split never adds one, and a vertex (with
// everything merged into it) snaps into each input edge at most 4 times, so the number of splits
// is bounded by vertices x input edges near them; on top, a cap on operations. After the queue
// drains, a full scan of every vertex re-checks the fix-point (events hidden behind a constraint
// that later moved are found there); the loop ends when a scan applies nothing.
#include "core/mesh.hpp"

#include <cstddef>
#include <vector>

namespace trisnap::detail {

struct SnapperParams {
    double vertex_threshold = 0; ///< merge when <= this
    double edge_threshold = 0;   ///< case 4 when < this
    double sliver_threshold = 0; ///< case 3 when <= this
    std::size_t max_operations = 0;
};

struct SnapperOutcome {
    std::size_t merges = 0;
    std::size_t splits = 0;
    std::size_t rounds = 0;
    std::size_t guarded = 0;    ///< splits refused by the repeated-split guard
    bool converged = true;      ///< false when the operation cap stopped the run
    /// Vertices still closer than the thresholds after the run (cap reached or guard refused).
    std::vector<std::uint32_t> unresolved;
};

SnapperOutcome run_snapper(Mesh& mesh, const SnapperParams& params);

} // namespace trisnap::detail
