#pragma once
// Rebuilds output geometry from the snapped triangulation.
// Polygons: the boundary of a feature's faces, traced with the feature on the left; at a vertex
// where the feature touches itself the trace stays within one sector, and a cycle that still
// visits a vertex twice is cut there into simple loops. Counter-clockwise loops are shells (one
// per edge-connected group of faces), clockwise loops are holes of the shell of their group. The
// result is OGC-valid by construction: simple rings, holes touching shells at points at most.
// Lines: the sub-edges of the line's input edges, chained in input order.
// Output is canonical: rings start at their lexicographically smallest vertex, parts and holes
// are sorted by that vertex.
#include "core/geometry.hpp"
#include "core/mesh.hpp"

#include <vector>

namespace trisnap::detail {

struct ExtractOptions {
    double grid = 0.0; ///< round output coordinates to multiples of this (0: none)
    bool has_z = false;
};

Geometry extract_polygons(Mesh& mesh, const std::vector<cdt::Face_handle>& faces,
                          const ExtractOptions& options);

/// Directed sub-edges of each line feature's constraints, bucketed by feature index.
struct LineEdge {
    std::uint32_t part, seg, order, from, to;
};
std::vector<std::vector<LineEdge>> collect_line_edges(Mesh& mesh, std::size_t feature_count);

/// Chains one line feature's edges, starting each part at where its first input vertex went.
Geometry extract_lines(Mesh& mesh, std::vector<LineEdge> edges,
                       const std::vector<std::uint32_t>& part_starts, const ExtractOptions& options);

} // namespace trisnap::detail
