#pragma once
// The only points the engine constructs: where two edges cross, and the foot of a perpendicular
// on an edge. Each is computed exactly (rational arithmetic on the stored doubles) and then
// rounded once, each coordinate to the nearest double (ties to even), so it is within half an
// ulp per coordinate of the true point: never CGAL's double-precision fallback, never an
// endpoint chosen instead.
//
// Why rounding cannot break the result: a rounded crossing p lies within ~1 ulp of both edges,
// not on them. The engine then routes both edges through p (each is split into two pieces that
// meet at p) and inserts those pieces with the same exact walk as any other edge; a piece that
// now crosses a third edge (possible only within an ulp of p) is split at that crossing in turn
// (core/mesh_insert.cpp), so the triangulation never holds two crossing constraints. The pieces
// deviate from the input edges by a few ulps (at most 2.5, see k_crossing_snap_ulps), while t is
// at least 256 ulps of every coordinate (input_cleaning rejects coordinates too large for that,
// problem 109): the drift they add is below t/100, and the separations are measured on the rounded points themselves. Any vertex or
// edge the rounding brought within t of another (a new near-crossing) is found by the snapper's
// searches like every other close pair and merged or split away.
#include "core/cdt_types.hpp"

namespace trisnap::detail {

/// The crossing of segments a-b and c-d, rounded to the nearest doubles. Precondition: the
/// segments cross at one point (their supporting lines are not parallel).
cdt::Point rounded_crossing(const cdt::Point& a, const cdt::Point& b, const cdt::Point& c,
                            const cdt::Point& d);

/// How close, in ulps of each coordinate, a rounded crossing may come to an end of one of the
/// two segments before that end is used instead: a crossing of two edges that end within ulps
/// of each other otherwise rounds past the ends and makes the pieces cross again (they crept
/// along one ulp per split on Monaco). The end is within 2 ulps of the crossing, so the
/// rerouted edge bends by at most 2.5 ulps, still far below t.
inline constexpr int k_crossing_snap_ulps = 2;

/// True when |p.x - q.x| <= k ulps of q.x and |p.y - q.y| <= k ulps of q.y.
bool within_ulps(const cdt::Point& p, const cdt::Point& q, int k);

/// True when p lies within k ulps (of its larger coordinate) of the segment s0-s1, measured
/// exactly. An end of one edge that close to the other edge takes their crossing: where the two
/// edges meet at a shallow angle the rounded crossing can land several ulps from both ends
/// (about ulp / sin(angle) along them), beyond what within_ulps() catches, and the pieces then
/// crossed again a few ulps further on, without end (Monaco's lines crept 2 ulps per split).
/// Routing the other edge through that end bends it by at most k ulps, whatever the angle.
bool within_ulps_of_segment(const cdt::Point& p, const cdt::Point& s0, const cdt::Point& s1, int k);

/// The foot of the perpendicular from p on the line through b and c (b != c), rounded.
cdt::Point rounded_projection(const cdt::Point& p, const cdt::Point& b, const cdt::Point& c);

} // namespace trisnap::detail
