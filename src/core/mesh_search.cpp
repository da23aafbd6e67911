// Local searches: walks over the faces that meet a disk (around a vertex) or a capsule (around an
// edge). They cross constrained edges on purpose: a vertex hidden behind a closer constraint is
// still within reach, and its event simply comes later in distance order. Cost is the number of
// faces meeting the region; distances are compared squared (no square roots), and the walk
// reuses one stack, so a search allocates nothing once the buffers have grown.
#include "core/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace trisnap::detail {
namespace {

double cross(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

double squared_segment_distance(double ax, double ay, double bx, double by, double cx, double cy, double dx,
                                double dy)
{
    const double o1 = cross(ax, ay, bx, by, cx, cy);
    const double o2 = cross(ax, ay, bx, by, dx, dy);
    const double o3 = cross(cx, cy, dx, dy, ax, ay);
    const double o4 = cross(cx, cy, dx, dy, bx, by);
    if (((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0))) {
        return 0.0;
    }
    return std::min({squared_distance_point_segment(ax, ay, cx, cy, dx, dy),
                     squared_distance_point_segment(bx, by, cx, cy, dx, dy),
                     squared_distance_point_segment(cx, cy, ax, ay, bx, by),
                     squared_distance_point_segment(dx, dy, ax, ay, bx, by)});
}

// Walks the faces meeting a region from the faces around `start`. `meets(a, b)` says whether the
// segment between two vertices meets the region; `visit(face)` sees each face once.
template <class Meets, class Visit>
void walk_region(cdt::Triangulation& tri, cdt::Vertex_handle start, std::uint32_t stamp,
                 std::vector<cdt::Face_handle>& stack, Meets&& meets, Visit&& visit)
{
    stack.clear();
    auto fc = tri.incident_faces(start);
    if (fc == nullptr) {
        return;
    }
    const auto done = fc;
    do {
        if (!tri.is_infinite(fc) && fc->info().mark != stamp) {
            fc->info().mark = stamp;
            stack.push_back(fc);
        }
    } while (++fc != done);
    while (!stack.empty()) {
        const cdt::Face_handle f = stack.back();
        stack.pop_back();
        visit(f);
        for (int i = 0; i < 3; ++i) {
            const cdt::Face_handle n = f->neighbor(i);
            if (tri.is_infinite(n) || n->info().mark == stamp) {
                continue;
            }
            if (!meets(f->vertex(cdt::Triangulation::cw(i)), f->vertex(cdt::Triangulation::ccw(i)))) {
                continue;
            }
            n->info().mark = stamp;
            stack.push_back(n);
        }
    }
}

} // namespace

double distance_point_segment(double px, double py, double ax, double ay, double bx, double by)
{
    const double dx = bx - ax;
    const double dy = by - ay;
    const double len2 = dx * dx + dy * dy;
    const double s = std::clamp(len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0, 0.0, 1.0);
    return std::hypot(px - (ax + s * dx), py - (ay + s * dy));
}

void Mesh::set_long_edge_length2(double len2)
{
    drop_long_index();
    m_long_index_tried = false;
    m_floored_walks = 0;
    m_floored_faces = 0;
    m_long2 = len2;
    m_long_edges = 0;
    m_edge_owners.for_each_edge([&](std::uint32_t a, std::uint32_t b) { count_edge(a, b, 1); });
}

// Most long edges are indexed; the few too long for the grid (LongEdgeIndex::max_cells) are
// checked one by one. More than this many of them and the grid is not worth keeping.
namespace {
constexpr std::size_t k_max_long_apart = 64;
}

// Appends the long edges within sqrt(r2_edge) of v that are not at v and not in `edges` yet (the
// walk met them): from v's cell of the grid and the few edges too long for it. Where v lies
// beyond the grid's range, every long edge is looked at (LongEdgeIndex::each says so).
void Mesh::add_long_edges_near(std::uint32_t v, double r2_edge, std::vector<EdgeHit>& edges) const
{
    const Xy rv = xy(v);
    const std::size_t walked = edges.size();
    const auto consider = [&](std::uint64_t key) {
        const auto a = static_cast<std::uint32_t>(key >> 32);
        const auto b = static_cast<std::uint32_t>(key);
        if (a == v || b == v) {
            return;
        }
        const Xy ra = xy(a);
        const Xy rb = xy(b);
        const double d2 = squared_distance_point_segment(rv.x, rv.y, ra.x, ra.y, rb.x, rb.y);
        if (d2 > r2_edge) {
            return;
        }
        const auto met = std::find_if(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(walked),
                                      [&](const EdgeHit& h) { return h.b == a && h.c == b; });
        if (met == edges.begin() + static_cast<std::ptrdiff_t>(walked)) {
            edges.push_back(EdgeHit{d2, a, b});
        }
    };
    if (!m_long_index.each(rv.x, rv.y, consider)) {
        m_edge_owners.for_each_edge([&](std::uint32_t a, std::uint32_t b) {
            if (is_long(a, b)) {
                consider(edge_key(a, b));
            }
        });
        return;
    }
    std::for_each(m_long_apart.begin(), m_long_apart.end(), consider);
}

// The grid pays once the walks held at the edge radius average more than 32 faces (a dense
// layer at a tolerance near its features' size); on real layers at their tolerances they walk a
// few faces and no grid is built.
void Mesh::note_floored_walk(std::size_t faces, double r2_edge)
{
    ++m_floored_walks;
    m_floored_faces += faces;
    if (m_floored_walks >= 256 && m_floored_faces > 32 * m_floored_walks) {
        build_long_index(r2_edge);
    }
}

void Mesh::build_long_index(double r2_edge)
{
    m_long_index_tried = true;
    m_long_index.reset(r2_edge);
    m_long_apart.clear();
    m_long_indexed = true;
    m_edge_owners.for_each_edge([&](std::uint32_t a, std::uint32_t b) {
        if (m_long_indexed && is_long(a, b)) { // (a drop stops the indexing)
            index_long_edge(a, b, 1);
        }
    });
}

// The lower id's point first, so that insert and erase compute the same cells.
void Mesh::index_long_edge(std::uint32_t a, std::uint32_t b, int delta)
{
    const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
    const Xy rl = xy(lo);
    const Xy rh = xy(hi);
    const std::uint64_t key = edge_key(lo, hi);
    if (delta > 0) {
        if (!m_long_index.insert(rl.x, rl.y, rh.x, rh.y, key)) {
            m_long_apart.push_back(key);
        }
    } else if (!m_long_index.erase(rl.x, rl.y, rh.x, rh.y, key)) {
        const auto at = std::find(m_long_apart.begin(), m_long_apart.end(), key);
        if (at != m_long_apart.end()) {
            *at = m_long_apart.back();
            m_long_apart.pop_back();
        }
    }
    // Bounded memory: at most 8 cell entries per vertex slot (a few per long edge is usual).
    // Dropped for good: m_long_index_tried stays set, so the walks hold the edge radius again.
    if (m_long_apart.size() > k_max_long_apart || m_long_index.entries() > 8 * m_vertices.size() + 4096) {
        drop_long_index();
    }
}

void Mesh::drop_long_index()
{
    m_long_indexed = false;
    m_long_index = LongEdgeIndex{};
    std::vector<std::uint64_t>().swap(m_long_apart);
}

std::uint32_t Mesh::next_stamp()
{
    if (++m_stamp == cdt::k_stamp_limit) { // wrapped: clear every mark once
        for (auto f : m_tri.all_face_handles()) {
            f->info().mark = 0;
        }
        m_stamp = 1;
    }
    return m_stamp;
}

void Mesh::search_point(std::uint32_t v, double r2_vertex, double r2_edge,
                        std::vector<std::pair<double, std::uint32_t>>& vertices, std::vector<EdgeHit>& edges,
                        bool nearest_only, const std::unordered_set<std::uint64_t>* passed_over)
{
    vertices.clear();
    edges.clear();
    if (m_tri.dimension() < 2) {
        return;
    }
    m_seen.clear();
    const std::uint32_t stamp = next_stamp();
    const Xy rv = xy(v);
    double reach2 = std::max(r2_vertex, r2_edge);
    // The edge radius bounds the shrinking only while an edge long enough for an event exists,
    // until the long edges' grid is built (note_floored_walk): from then on a nearest-only walk
    // shrinks freely and the long edges within the edge radius come from the grid.
    const bool from_grid = nearest_only && m_long_edges > 0 && r2_edge > 0 && m_long_indexed &&
                           r2_edge <= m_long_index.radius2();
    const double floor2 = m_long_edges > 0 && r2_edge > 0 && !from_grid ? r2_edge : 0.0;
    const std::size_t faces_before = m_faces_walked;
    double best2 = std::numeric_limits<double>::infinity();
    // The points straight from the CGAL vertices the walk holds (they are the vertices' points).
    const auto seg_dist2 = [&](cdt::Vertex_handle a, cdt::Vertex_handle b) {
        const cdt::Point& ra = a->point();
        const cdt::Point& rb = b->point();
        return squared_distance_point_segment(rv.x, rv.y, ra.x(), ra.y(), rb.x(), rb.y());
    };
    // Records vertex w's squared distance once per search. With `nearest_only` only vertices as
    // near as the nearest so far are kept, and the walk shrinks to the nearest distance d plus a
    // margin (but not below the edge radius while a long edge exists: m_long_edges): anything
    // nearer than the nearest lies in that disk, and the faces meeting a disk around v are
    // connected through edges meeting it, so the walk still reaches them. The margin, d / 8 but
    // at least 64 ulps of the largest coordinate, is far above the rounding of the distances
    // (a few ulps of the coordinates), so a vertex as near as the nearest is never lost to it.
    // In a cluster of k vertices within t this keeps the walk near v instead of over all k.
    // Without a long edge no edge within the edge radius can give the caller an event (see
    // Snapper::discover_segment): the walk then shrinks below it too, and `edges` holds only
    // the edges it met (a tolerance larger than the features walked the whole layer per vertex:
    // one CLC polygon of 44 k vertices at 0.5 degrees took 300 s).
    const auto see_vertex = [&](cdt::Vertex_handle h) {
        if (!std::isnan(seen_d2(h))) {
            return;
        }
        const std::uint32_t w = h->info().id;
        const double d2 = point_d2(rv, Xy{h->point().x(), h->point().y()}); // vertex_d2(v, w)
        mark_seen(h, d2);
        if (d2 > r2_vertex) {
            return;
        }
        if (!nearest_only) {
            vertices.emplace_back(d2, w);
        } else if (d2 <= best2) {
            vertices.emplace_back(d2, w);
            if (d2 < best2 && (passed_over == nullptr || passed_over->count(edge_key(v, w)) == 0)) {
                best2 = d2;
                const double d = std::sqrt(d2);
                const double r = d + std::max(d / 8, m_ulp_margin);
                reach2 = std::max(std::min(reach2, r * r), floor2);
            }
        }
    };
    const auto visit_face = [&](cdt::Face_handle f) {
        ++m_faces_walked;
        for (int i = 0; i < 3; ++i) {
            see_vertex(f->vertex(i));
            // A constrained edge in reach meets the region, so the walk visits both its faces:
            // take it from one of them (the order of `edges` means nothing to the callers).
            if (!f->is_constrained(i) || (f->neighbor(i) < f && !m_tri.is_infinite(f->neighbor(i)))) {
                continue;
            }
            const cdt::Vertex_handle ha = f->vertex(cdt::Triangulation::cw(i));
            const cdt::Vertex_handle hb = f->vertex(cdt::Triangulation::ccw(i));
            const std::uint32_t a = ha->info().id;
            const std::uint32_t b = hb->info().id;
            if (a == v || b == v) {
                continue;
            }
            const double d2 = seg_dist2(ha, hb);
            if (d2 <= r2_edge) {
                edges.push_back(EdgeHit{d2, std::min(a, b), std::max(a, b)});
            }
        }
    };
    const cdt::Vertex_handle hv = handle(v);
    mark_seen(hv, 0);
    if (nearest_only) {
        // v's neighbours first (in a constrained Delaunay triangulation the nearest visible
        // vertex is one of them): the walk starts with its reach already shrunk.
        auto vc = m_tri.incident_vertices(hv);
        const auto done = vc;
        do {
            if (!m_tri.is_infinite(vc)) {
                see_vertex(vc);
            }
        } while (++vc != done);
    }
    // An edge with an end in reach meets the disk: the ends' distances (the face was visited
    // first) decide most edges without the distance to the segment.
    walk_region(m_tri, hv, stamp, m_walk,
                [&](cdt::Vertex_handle a, cdt::Vertex_handle b) {
                    return seen_d2(a) <= reach2 || seen_d2(b) <= reach2 || seg_dist2(a, b) <= reach2;
                },
                visit_face);
    if (from_grid) {
        add_long_edges_near(v, r2_edge, edges);
    } else if (nearest_only && floor2 > 0 && !m_long_index_tried) {
        note_floored_walk(m_faces_walked - faces_before, r2_edge);
    }
}

void Mesh::search_segment(std::uint32_t b, std::uint32_t c, double r2,
                          std::vector<std::pair<double, std::uint32_t>>& vertices)
{
    vertices.clear();
    if (m_tri.dimension() < 2) {
        return;
    }
    m_seen.clear();
    const std::uint32_t stamp = next_stamp();
    const Xy rb = xy(b);
    const Xy rc = xy(c);
    const cdt::Vertex_handle hb = handle(b);
    mark_seen(hb, 0);
    mark_seen(handle(c), 0);
    // Start from the faces around b: two of them hold the edge, so the walk with the capsule
    // test covers the whole edge.
    walk_region(
        m_tri, hb, stamp, m_walk,
        [&](cdt::Vertex_handle p, cdt::Vertex_handle q) {
            if (seen_d2(p) <= r2 || seen_d2(q) <= r2) { // an end in the capsule (as above)
                return true;
            }
            const cdt::Point& rp = p->point();
            const cdt::Point& rq = q->point();
            return squared_segment_distance(rb.x, rb.y, rc.x, rc.y, rp.x(), rp.y(), rq.x(), rq.y()) <= r2;
        },
        [&](cdt::Face_handle f) {
            ++m_faces_walked;
            for (int i = 0; i < 3; ++i) {
                const cdt::Vertex_handle h = f->vertex(i);
                if (!std::isnan(seen_d2(h))) {
                    continue;
                }
                const std::uint32_t w = h->info().id;
                const cdt::Point& rw = h->point();
                const double d2 = squared_distance_point_segment(rw.x(), rw.y(), rb.x, rb.y, rc.x, rc.y);
                mark_seen(h, d2);
                if (d2 <= r2) {
                    vertices.emplace_back(d2, w);
                }
            }
        });
}

} // namespace trisnap::detail
