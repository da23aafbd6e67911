#pragma once
// Exact geometric predicates on the engine's plain coordinates, for every module that decides
// topology (orientation, inside/outside, angular order) on doubles: the assembler, tile input
// cutting, stitching. They evaluate the sign of the exact expression on the stored doubles
// (CGAL's filtered predicates: interval arithmetic first, exact arithmetic when that cannot
// decide), so "collinear", "on the boundary" and "same direction" are never rounding accidents.
// Point identity is exact equality of x and y.
#include "core/geometry.hpp"

#include <vector>

namespace trisnap {

/// +1 when r lies to the left of the directed line p->q (p, q, r counter-clockwise), -1 to the
/// right, 0 when the three points are collinear.
int orientation(const Coord& p, const Coord& q, const Coord& r);

/// Lexicographic order of points (x, then y): the canonical order of the engine's output.
inline bool xy_less(const Coord& a, const Coord& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; }

/// Counter-clockwise order of the directions from `v` to `a` and to `b`, by angle in [0, 2pi)
/// measured from the positive x axis. Exact; equal directions compare equal.
bool direction_less(const Coord& v, const Coord& a, const Coord& b);

/// Whether the closed segment p-q meets the closed box [xmin, xmax] x [ymin, ymax] (sides may
/// be infinite). Exact: the box is clipped to the segment's own bounding box, of which the
/// segment is a diagonal, so it meets the clipped box unless all four corners lie strictly on
/// one side of its line. Tile input cutting and the shared-boundary evidence both ask it.
bool segment_meets_box(const Coord& p, const Coord& q, double xmin, double ymin, double xmax, double ymax);

/// What the horizontal ray from `p` towards +x does at the segment a-b, with the half-open rule
/// (the segment counts when exactly one end lies strictly above p): the step of a crossing
/// number that stays exact at vertices and horizontal edges.
enum class RayStep { misses, crosses, on_segment };
RayStep ray_step(const Coord& a, const Coord& b, const Coord& p);

/// Where `p` lies with respect to the ring (open or closed, any orientation): +1 inside, -1
/// outside, 0 on its boundary. Exact; O(ring size).
int locate_in_ring(const std::vector<Coord>& ring, const Coord& p);

} // namespace trisnap
