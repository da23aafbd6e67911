#include "core/extraction.hpp"

#include <cmath>

namespace trisnap::detail {

Coord output_coord(const Mesh& mesh, std::uint32_t v, const ExtractOptions& o)
{
    const VertexRecord& r = mesh.vertex(v);
    return round_to_grid(Coord{r.x, r.y, o.has_z ? mesh.z(v) : std::nan("")}, o.grid);
}

// A face's edge i runs from vertex ccw(i) to vertex cw(i) with the face on its left (CGAL's
// faces are counter-clockwise); it is on the feature's boundary when the neighbour across it
// is not one of the feature's faces.
Geometry extract_polygons(Mesh& mesh, std::span<const cdt::Face_handle> faces,
                          const ExtractOptions& options)
{
    const std::uint32_t stamp = mesh.fresh_stamp();
    for (const cdt::Face_handle f : faces) {
        f->info().mark = stamp;
    }
    std::vector<DirectedEdge> edges;
    for (const cdt::Face_handle f : faces) {
        for (int i = 0; i < 3; ++i) {
            if (f->neighbor(i)->info().mark == stamp) {
                continue;
            }
            const std::uint32_t a = f->vertex(cdt::Triangulation::ccw(i))->info().id;
            const std::uint32_t b = f->vertex(cdt::Triangulation::cw(i))->info().id;
            edges.push_back(DirectedEdge{output_coord(mesh, a, options), output_coord(mesh, b, options)});
        }
    }
    return assemble_polygons(std::move(edges), options.has_z);
}

} // namespace trisnap::detail
