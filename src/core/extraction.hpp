#pragma once
// Output geometry from the snapped triangulation: each feature's directed boundary edges (the
// edges between its faces and the others, the feature on the left) or its lines' sub-edges,
// in output coordinates, handed to the one assembler (core/assemble.hpp) that tiles use too.
#include "core/assemble.hpp"
#include "core/geometry.hpp"
#include "core/mesh.hpp"

#include <span>
#include <vector>

namespace trisnap::detail {

struct ExtractOptions {
    double grid = 0.0; ///< round output coordinates to multiples of this (0: none)
    bool has_z = false;
};

/// The output coordinate of a vertex (grid-rounded, z only when the feature has z).
Coord output_coord(const Mesh& mesh, std::uint32_t v, const ExtractOptions& options);

Geometry extract_polygons(Mesh& mesh, std::span<const cdt::Face_handle> faces,
                          const ExtractOptions& options);

/// Directed sub-edges of each line feature's constraints, bucketed by feature index.
struct LineEdge {
    std::uint32_t from, to;
};
std::vector<std::vector<LineEdge>> collect_line_edges(Mesh& mesh, std::size_t feature_count);

/// Chains one line feature's edges; `part_starts` are its parts' first input points.
Geometry extract_lines(const Mesh& mesh, const std::vector<LineEdge>& edges,
                       const std::vector<Coord>& part_starts, const ExtractOptions& options);

} // namespace trisnap::detail
