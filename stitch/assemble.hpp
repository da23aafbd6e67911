#pragma once
// Rebuilds one feature from the directed edges its tiles own, with the engine's rules (see
// src/core/extraction.hpp), so a feature assembled from several tiles is the feature the
// engine would have traced: boundary traced with the feature on the left, staying within one
// sector at a vertex where it touches itself, cycles that revisit a vertex cut there;
// counter-clockwise loops are shells, clockwise loops holes of the innermost shell holding
// them; rings start at their smallest vertex, holes and parts sorted by it.
#include "stitch/edges.hpp"

#include <vector>

namespace trisnap::stitch {

Geometry assemble_polygons(std::vector<Edge> edges, bool has_z);

/// Lines: edges chained into paths, first from the input parts' first points (in part order)
/// where those did not move, then where a path must start (more edges leave a vertex than
/// reach it), then closed chains from their smallest edge.
Geometry assemble_lines(std::vector<Edge> edges, const std::vector<Coord>& part_starts, bool has_z);

/// The engine's canonical order of rings and parts (used on tiles' own output too).
void canonicalise(Geometry& g);

} // namespace trisnap::stitch
