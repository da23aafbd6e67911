#pragma once
// Directed edges -> geometry: the one place where output rings and lines are built. The engine
// hands in the boundary edges of a feature's faces in its triangulation; the tiled path hands
// in the edges of a feature that the tiles own (stitch/). Both hand in the same edges for the
// same feature when the seams agree, so tiled and untiled output are equal by construction.
//
// Polygons (after the TU Delft tracing used by prepair): the boundary is traced with the feature
// on the left; at a vertex where the feature touches itself the trace stays within one sector
// (the next edge is the first out-edge clockwise from the way back), and a cycle that still
// visits a vertex twice is cut there into simple loops. Counter-clockwise loops are shells,
// clockwise loops holes of the innermost shell holding them. The result is OGC-valid when the
// edges are those of a planar subdivision (no two cross or overlap): simple rings, holes
// touching shells at points at most.
// Lines: edges chained into paths, first from the parts' start points (in part order), then
// from where a path must start (more edges leave a vertex than reach it), then closed chains
// from their smallest edge; a closed chain through a vertex of a traced path is spliced into it.
// Output is canonical: rings start at their lexicographically smallest vertex, holes and parts
// are sorted by that vertex. Every decision is exact (core/predicates.hpp): orientation and
// angular order by exact predicates, point identity by exact equality of x and y.
#include "core/geometry.hpp"

#include <vector>

namespace trisnap {

/// One directed edge of a feature's output: of a polygon's boundary (the feature on its left)
/// or of one of its lines. z is carried, never used to decide anything.
struct DirectedEdge {
    Coord a;
    Coord b;
};

/// Appends the directed edges of a polygon's closed rings (each ring's consecutive points).
void append_ring_edges(const Polygon& polygon, std::vector<DirectedEdge>& out);

/// Rings from the boundary edges of one polygonal feature. Repeated edges are kept once and
/// zero-length edges dropped; loops that close with fewer than three vertices and holes that no
/// shell holds (impossible for a planar subdivision) are dropped.
/// `finished`: polygons of the same feature traced already (by this function: closed,
/// canonical) from a subset of its edges that holds every edge of the feature lying inside
/// them; their edges are not in `edges`. One that shares no vertex (x, y) with `edges` or with
/// another finished polygon joins the output as it is, one that does is traced again with
/// `edges`: the output is the one all the edges together give (the stitch's tiles hand in the
/// polygons inside their cores this way).
Geometry assemble_polygons(std::vector<DirectedEdge> edges, bool has_z, std::vector<Polygon> finished = {});

/// Paths from the edges of one line feature. `part_starts`: where each input part begins (the
/// caller rounds them as it rounds the edges).
Geometry assemble_lines(std::vector<DirectedEdge> edges, const std::vector<Coord>& part_starts, bool has_z);

/// Rounds x and y to multiples of g (g = 0: unchanged), without negative zeros; z is kept.
Coord round_to_grid(Coord c, double g);

} // namespace trisnap
