// Local searches: breadth-first walks over the faces that meet a disk (around a vertex) or a
// capsule (around an edge). They cross constrained edges on purpose: a vertex hidden behind a
// closer constraint is still within reach, and its event simply comes later in distance order.
// Cost is the number of faces meeting the region, so the snapper's total work is near-linear.
#include "core/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace trisnap::detail {
namespace {

double cross(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

double segment_distance(double ax, double ay, double bx, double by,
                        double cx, double cy, double dx, double dy)
{
    const double o1 = cross(ax, ay, bx, by, cx, cy), o2 = cross(ax, ay, bx, by, dx, dy);
    const double o3 = cross(cx, cy, dx, dy, ax, ay), o4 = cross(cx, cy, dx, dy, bx, by);
    if (((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0))) return 0.0;
    return std::min({distance_point_segment(ax, ay, cx, cy, dx, dy),
                     distance_point_segment(bx, by, cx, cy, dx, dy),
                     distance_point_segment(cx, cy, ax, ay, bx, by),
                     distance_point_segment(dx, dy, ax, ay, bx, by)});
}

} // namespace

std::uint32_t Mesh::next_stamp()
{
    if (++m_stamp == 0) { // wrapped: clear every mark once
        for (auto f : m_tri.all_face_handles()) f->info().stamp = 0;
        std::fill(m_vertex_stamp.begin(), m_vertex_stamp.end(), 0u);
        m_stamp = 1;
    }
    return m_stamp;
}

// Walks the faces meeting a region. `meets(a, b)` says whether the segment between two vertex
// ids meets the region; `visit(face)` sees each face once.
template <class Meets, class Visit>
static void walk_region(cdt::Triangulation& tri, cdt::Vertex_handle start, std::uint32_t stamp,
                        Meets&& meets, Visit&& visit)
{
    std::deque<cdt::Face_handle> queue;
    auto fc = tri.incident_faces(start), done = fc;
    if (fc == nullptr) return;
    do {
        if (tri.is_infinite(fc) || fc->info().stamp == stamp) continue;
        fc->info().stamp = stamp;
        queue.push_back(fc);
    } while (++fc != done);
    while (!queue.empty()) {
        const cdt::Face_handle f = queue.front();
        queue.pop_front();
        visit(f);
        for (int i = 0; i < 3; ++i) {
            const cdt::Face_handle n = f->neighbor(i);
            if (tri.is_infinite(n) || n->info().stamp == stamp) continue;
            if (!meets(f->vertex(tri.cw(i))->info().id, f->vertex(tri.ccw(i))->info().id)) continue;
            n->info().stamp = stamp;
            queue.push_back(n);
        }
    }
}

void Mesh::search_point(std::uint32_t v, double r_vertex, double r_edge,
                        std::vector<std::pair<double, std::uint32_t>>& vertices,
                        std::vector<EdgeHit>& edges)
{
    vertices.clear();
    edges.clear();
    if (m_tri.dimension() < 2) return;
    const std::uint32_t stamp = next_stamp();
    const VertexRecord& rv = m_vertices[v];
    const double reach = std::max(r_vertex, r_edge);
    const auto seg_dist = [&](std::uint32_t a, std::uint32_t b) {
        const VertexRecord &ra = m_vertices[a], &rb = m_vertices[b];
        return distance_point_segment(rv.x, rv.y, ra.x, ra.y, rb.x, rb.y);
    };
    m_vertex_stamp[v] = stamp;
    walk_region(m_tri, rv.handle, stamp,
        [&](std::uint32_t a, std::uint32_t b) { return seg_dist(a, b) <= reach; },
        [&](cdt::Face_handle f) {
            for (int i = 0; i < 3; ++i) {
                const std::uint32_t w = f->vertex(i)->info().id;
                if (m_vertex_stamp[w] != stamp) {
                    m_vertex_stamp[w] = stamp;
                    const double d = std::hypot(m_vertices[w].x - rv.x, m_vertices[w].y - rv.y);
                    if (d <= r_vertex) vertices.emplace_back(d, w);
                }
                if (!f->is_constrained(i)) continue;
                std::uint32_t a = f->vertex(m_tri.cw(i))->info().id, b = f->vertex(m_tri.ccw(i))->info().id;
                if (a == v || b == v) continue;
                const double d = seg_dist(a, b);
                if (d <= r_edge) edges.push_back(EdgeHit{d, std::min(a, b), std::max(a, b)});
            }
        });
    std::sort(edges.begin(), edges.end(), [](const EdgeHit& p, const EdgeHit& q) {
        return std::tie(p.b, p.c) < std::tie(q.b, q.c);
    });
    edges.erase(std::unique(edges.begin(), edges.end(), [](const EdgeHit& p, const EdgeHit& q) {
        return p.b == q.b && p.c == q.c;
    }), edges.end());
}

void Mesh::search_segment(std::uint32_t b, std::uint32_t c, double r,
                          std::vector<std::pair<double, std::uint32_t>>& vertices)
{
    vertices.clear();
    if (m_tri.dimension() < 2) return;
    const std::uint32_t stamp = next_stamp();
    const VertexRecord &rb = m_vertices[b], &rc = m_vertices[c];
    m_vertex_stamp[b] = m_vertex_stamp[c] = stamp;
    // Start from the faces on the edge: both are incident to b, so the walk from b with the
    // capsule test covers the whole edge.
    walk_region(m_tri, rb.handle, stamp,
        [&](std::uint32_t p, std::uint32_t q) {
            const VertexRecord &rp = m_vertices[p], &rq = m_vertices[q];
            return segment_distance(rb.x, rb.y, rc.x, rc.y, rp.x, rp.y, rq.x, rq.y) <= r;
        },
        [&](cdt::Face_handle f) {
            for (int i = 0; i < 3; ++i) {
                const std::uint32_t w = f->vertex(i)->info().id;
                if (m_vertex_stamp[w] == stamp) continue;
                m_vertex_stamp[w] = stamp;
                const VertexRecord& rw = m_vertices[w];
                const double d = distance_point_segment(rw.x, rw.y, rb.x, rb.y, rc.x, rc.y);
                if (d <= r) vertices.emplace_back(d, w);
            }
        });
}

} // namespace trisnap::detail
