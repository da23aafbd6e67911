#pragma once
// What the engine reports from the triangulation itself, beside the output geometry: input rings
// that cross or overlap (105), input edge pieces that no longer bound their polygon (209), how
// far each feature's edges strayed (max_displacement), and vertices the snapper could not
// settle (205/207). Each reads the owner table once; evidence counts only inside `region`, so
// tiles report each piece of it exactly once.
#include "core/labelling.hpp"
#include "core/mesh.hpp"
#include "core/problems.hpp"
#include "core/snap.hpp"
#include "core/snapper.hpp"

#include <vector>

namespace trisnap::detail {

/// Per feature: true when its own input rings cross or overlap (checked on the input
/// triangulation): a sub-edge it owns twice, or a vertex lying inside two of its input edges.
/// A ring vertex touching another edge is not flagged (valid for a hole on its shell).
std::vector<bool> self_intersecting(const Mesh& mesh, std::size_t features, const Region& region);

/// Per feature: the largest distance from a vertex now on one of its input edges to that input
/// edge (a cascade of splits can bend an edge further than any single vertex moved). The input
/// edge is read from its ends' records (Mesh::owner_from, owner_to), which never move.
std::vector<double> edge_deviation(const Mesh& mesh, std::size_t features, const Region& region);

/// Each polygon's input edge pieces that have the same membership on both sides (owned an even
/// number of times): how many, and the smallest one's midpoint. Read from the owner table,
/// before the outputs are made (Mesh::release_owners).
/// Only the polygons that have such pieces, by feature index (rare: two dense per-feature
/// tables were 32 bytes a feature, 7.9 MB of Andorra x43 at the untiled peak).
struct CollapsedEdge {
    std::uint32_t feature;
    std::size_t count;
    Coord where;
};
struct CollapsedEdges {
    std::vector<CollapsedEdge> found; ///< one per feature, by feature index
};
CollapsedEdges collapsed_edges(const Mesh& mesh, const Region& region);

/// 209 for every polygon (not collapsed entirely: `written[f]`) with such pieces, at the
/// smallest.
void report_collapsed_edges(const CollapsedEdges& found, const std::vector<Outline>& clean,
                            const std::vector<bool>& written, std::vector<Problem>& problems);

/// 205 (cap reached) or 207 (guard refused a split) for every feature with an edge at an
/// unresolved vertex; `grid` > 0: the message says the run was not rounded to it.
void report_unresolved(Mesh& mesh, const SnapperOutcome& outcome, const std::vector<Outline>& clean,
                       const Region& region, double grid, std::vector<Problem>& problems);

} // namespace trisnap::detail
