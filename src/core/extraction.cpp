#include "core/extraction.hpp"

#include <cmath>

namespace trisnap::detail {

Coord output_coord(const Mesh& mesh, std::uint32_t v, const ExtractOptions& o)
{
    const Xy r = mesh.xy(v);
    return round_to_grid(Coord{r.x, r.y, o.has_z ? mesh.z(v) : std::nan("")}, o.grid);
}

// A face's edge i runs from vertex ccw(i) to vertex cw(i) with the face on its left (CGAL's
// faces are counter-clockwise); it is on the feature's boundary when the neighbour across it
// is not one of the feature's faces.
void append_boundary_edges(Mesh& mesh, std::span<const cdt::Face_handle> faces, std::vector<IdEdge>& out)
{
    const std::uint32_t stamp = mesh.fresh_stamp();
    for (const cdt::Face_handle f : faces) {
        f->info().mark = stamp;
    }
    for (const cdt::Face_handle f : faces) {
        for (int i = 0; i < 3; ++i) {
            if (f->neighbor(i)->info().mark == stamp) {
                continue;
            }
            out.push_back(IdEdge{f->vertex(cdt::Triangulation::ccw(i))->info().id,
                                 f->vertex(cdt::Triangulation::cw(i))->info().id});
        }
    }
}

std::vector<DirectedEdge> directed_edges(const Mesh& mesh, std::span<const IdEdge> edges, const ExtractOptions& options)
{
    std::vector<DirectedEdge> directed;
    directed.reserve(edges.size());
    for (const IdEdge& e : edges) {
        directed.push_back(DirectedEdge{output_coord(mesh, e.from, options), output_coord(mesh, e.to, options)});
    }
    return directed;
}

Geometry assemble_boundary(const Mesh& mesh, std::span<const IdEdge> edges, const ExtractOptions& options)
{
    return assemble_polygons(directed_edges(mesh, edges, options), options.has_z);
}

} // namespace trisnap::detail
