#pragma once
// Output geometry from the snapped triangulation: each feature's directed boundary edges (the
// edges between its faces and the others, the feature on the left) or its lines' sub-edges,
// taken out by vertex id while the triangulation lives, then made output coordinates from the
// vertex records and handed to the one assembler (core/assemble.hpp) that tiles use too.
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

/// A directed edge between two vertices, by id. The outputs' edges are taken out of the
/// triangulation this way before it is freed (snap.cpp), and made coordinates after.
struct IdEdge {
    std::uint32_t from, to;
};

/// The edges in output coordinates (output_coord), in their order.
std::vector<DirectedEdge> directed_edges(const Mesh& mesh, std::span<const IdEdge> edges, const ExtractOptions& options);

/// Appends the boundary edges of a polygon feature's faces (the edges between them and the
/// other faces, the feature on the left), in the faces' order.
void append_boundary_edges(Mesh& mesh, std::span<const cdt::Face_handle> faces, std::vector<IdEdge>& out);

/// Rings from one polygon feature's boundary edges. Reads only the vertex records, so it runs
/// after Mesh::release_triangulation().
Geometry assemble_boundary(const Mesh& mesh, std::span<const IdEdge> edges, const ExtractOptions& options);

/// Directed sub-edges of the line features' constraints, grouped by feature index in one table
/// (a vector per feature was 24 bytes for every feature, lines or not: 5.9 MB of Andorra x43's
/// polygons at the untiled peak).
struct LineEdges {
    /// Feature f's edges are edges[first[f], first[f + 1]); empty when no feature has a line.
    std::vector<std::uint32_t> first;
    std::vector<IdEdge> edges;
    std::span<const IdEdge> of(std::size_t f) const
    {
        return first.empty() ? std::span<const IdEdge>{} : std::span<const IdEdge>(edges.data() + first[f], first[f + 1] - first[f]);
    }
};
LineEdges collect_line_edges(Mesh& mesh, std::size_t feature_count);

/// Chains one line feature's edges; `part_starts` are its parts' first input points. Reads only
/// the vertex records.
Geometry extract_lines(const Mesh& mesh, std::span<const IdEdge> edges,
                       const std::vector<Coord>& part_starts, const ExtractOptions& options);

} // namespace trisnap::detail
