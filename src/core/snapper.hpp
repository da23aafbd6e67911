#pragma once
// The fix-point driver: snapping events processed strictly smallest distance first.
//
// Events (d = the distance that triggers them, compared squared; ties by kind, then vertex ids,
// which are canonical, never addresses):
//   1 face   - a triangle whose three edges are all <= t collapses to its centroid (key: its
//              shortest edge, so it wins over that edge's own merge);
//   2 merge  - two vertices <= t apart, with no constraint between them, merge at the midpoint;
// Centroid and midpoint are weighted by how many vertices each side already stands for, so a
// cluster merged pair by pair lands on the mean of its members instead of drifting towards the
// last-merged one.
//   3 sliver - the apex of a triangle on a constrained base, <= sliver*t from it, moves onto the
//              base (split there);
//   4 edge   - a vertex < e*t from a constrained edge it is not on moves onto it (split).
// Cases 3 and 4 merge instead of moving when the vertex is <= t from an end of the edge: they
// leave that to the merge event, which avoids the ping-pong of two vertices snapping onto each
// other's edges with shrinking distances.
//
// Discovery: one scan of every vertex and face at the start; after that only what an edit
// changed is examined: the new vertex and the crossing vertices it made (merges and edges near
// them), every constrained edge it inserted (vertices near it), and every face CGAL created or
// changed (faces and slivers; core/tracked_face.hpp). An event's condition depends only on vertex
// positions (a moved vertex is a new vertex), constrained edges and faces, so nothing else can
// start to apply, except a merge refused because a constraint lay between the two vertices: such
// merges are parked and tried again when the queue has drained, until none goes through. Hence
// the queue drains at a fix-point without the full re-scan the first engine needed; the tests run
// with SnapperParams::verify, a full scan at the end that counts events still applicable
// (asserted to be 0).
//
// Termination: a merge removes at least one vertex; a split never adds one, and a vertex (with
// everything merged into it) snaps into each input edge at most 4 times, so the number of splits
// is bounded by vertices x input edges near them; on top, a cap on operations.
#include "core/mesh.hpp"

#include <cstddef>
#include <vector>

namespace trisnap::detail {

struct SnapperParams {
    double vertex_threshold = 0; ///< merge when <= this
    double edge_threshold = 0;   ///< case 4 when < this
    double sliver_threshold = 0; ///< case 3 when <= this
    std::size_t max_operations = 0;
    bool verify = false;         ///< after the run, count events a full scan still finds applicable
};

struct SnapperOutcome {
    std::size_t merges = 0;
    std::size_t splits = 0;
    std::size_t rounds = 0;     ///< passes over the queue: 1 + re-checks of parked merges
    std::size_t guarded = 0;    ///< splits refused by the repeated-split guard
    std::size_t faces_visited = 0; ///< faces the searches walked and changed faces examined
    std::size_t fixpoint_misses = 0; ///< with verify: applicable events left at the end
    std::size_t peak_queue = 0;  ///< most events the queue held at once (O(vertices), not O(pairs))
    std::size_t face_events = 0; ///< face collapse events queued (candidates, not every trivial face)
    bool converged = true;      ///< false when the operation cap stopped the run
    /// Vertices still closer than the thresholds after the run (cap reached or guard refused).
    std::vector<std::uint32_t> unresolved;
};

/// `meter` (optional) hears the snapping step: the first scan, then the queue drained.
SnapperOutcome run_snapper(Mesh& mesh, const SnapperParams& params, WorkMeter* meter = nullptr);

} // namespace trisnap::detail
