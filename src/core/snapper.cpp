#include "core/snapper.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <tuple>

namespace trisnap::detail {
namespace {

enum class Kind : std::uint8_t { face = 1, merge = 2, sliver = 3, edge = 4 };

struct Event {
    double d;
    Kind kind;
    std::uint32_t a, b, c; ///< face: a<b<c; merge: a<b; sliver/edge: vertex a, edge b<c
    bool operator>(const Event& o) const
    {
        return std::tie(d, kind, a, b, c) > std::tie(o.d, o.kind, o.a, o.b, o.c);
    }
};

// How often one vertex may be split into the same input edge. Once is enough on real layers;
// on dense overlapping synthetic tangles a vertex dragged off an edge by later merges can need a
// second or third split, and refusing left vertices at 0.28 t from edges. The bound keeps the
// termination argument (finitely many splits per vertex and edge).
constexpr std::ptrdiff_t k_max_snaps_per_edge = 4;

double dist(const VertexRecord& p, const VertexRecord& q) { return std::hypot(p.x - q.x, p.y - q.y); }

class Snapper {
public:
    Snapper(Mesh& mesh, const SnapperParams& p) : m_mesh(mesh), m_p(p) {}
    SnapperOutcome run();

private:
    void discover(std::uint32_t v);
    void discover_faces(std::uint32_t v);
    void discover_edges_of(std::uint32_t v);
    bool apply(const Event& e);
    bool apply_face(const Event& e);
    bool apply_merge(const Event& e);
    bool apply_split(const Event& e);
    bool visible(std::uint32_t a, std::uint32_t b);
    void after_edit(std::uint32_t w);
    void push(double d, Kind k, std::uint32_t a, std::uint32_t b, std::uint32_t c) { m_queue.push(Event{d, k, a, b, c}); }
    bool alive(std::uint32_t v) const { return m_mesh.vertex(v).alive; }
    std::size_t drain();
    void collect_unresolved();

    Mesh& m_mesh;
    SnapperParams m_p;
    SnapperOutcome m_out;
    std::priority_queue<Event, std::vector<Event>, std::greater<>> m_queue;
    std::vector<std::pair<double, std::uint32_t>> m_near;
    std::vector<EdgeHit> m_edges;
    std::vector<std::uint32_t> m_touched, m_owners;
    std::size_t m_ops = 0;
    std::size_t m_slots_before = 0;
};

void Snapper::discover(std::uint32_t v)
{
    const double r_edge = std::max(m_p.edge_threshold, 0.0);
    m_mesh.search_point(v, m_p.vertex_threshold, r_edge, m_near, m_edges);
    for (const auto& [d, w] : m_near) push(d, Kind::merge, std::min(v, w), std::max(v, w), 0);
    for (const EdgeHit& h : m_edges)
        if (h.d < m_p.edge_threshold) push(h.d, Kind::edge, v, h.b, h.c);
    discover_faces(v);
}

// Cases 1 and 3 are properties of triangles, so they are found on the faces around v.
void Snapper::discover_faces(std::uint32_t v)
{
    auto& tri = m_mesh.tri();
    auto fc = tri.incident_faces(m_mesh.vertex(v).handle), done = fc;
    if (fc == nullptr || tri.dimension() < 2) return;
    do {
        if (tri.is_infinite(fc)) continue;
        std::array<std::uint32_t, 3> ids{fc->vertex(0)->info().id, fc->vertex(1)->info().id, fc->vertex(2)->info().id};
        const int iv = fc->index(m_mesh.vertex(v).handle);
        const std::uint32_t b = ids[tri.cw(iv)], c = ids[tri.ccw(iv)];
        const VertexRecord &rv = m_mesh.vertex(v), &rb = m_mesh.vertex(b), &rc = m_mesh.vertex(c);
        if (m_p.sliver_threshold > 0 && fc->is_constrained(iv)) {
            const double d = distance_point_segment(rv.x, rv.y, rb.x, rb.y, rc.x, rc.y);
            if (d <= m_p.sliver_threshold) push(d, Kind::sliver, v, std::min(b, c), std::max(b, c));
        }
        const double e0 = dist(rv, rb), e1 = dist(rb, rc), e2 = dist(rc, rv);
        if (std::max({e0, e1, e2}) <= m_p.vertex_threshold) {
            std::sort(ids.begin(), ids.end());
            push(std::min({e0, e1, e2}), Kind::face, ids[0], ids[1], ids[2]);
        }
    } while (++fc != done);
}

// Vertices near the edges of v: a new or moved edge can come close to vertices far from v.
void Snapper::discover_edges_of(std::uint32_t v)
{
    auto& tri = m_mesh.tri();
    auto vc = tri.incident_vertices(m_mesh.vertex(v).handle), done = vc;
    if (vc == nullptr) return;
    std::vector<std::uint32_t> ends;
    do {
        if (!tri.is_infinite(vc) && m_mesh.is_constrained_edge(v, vc->info().id)) ends.push_back(vc->info().id);
    } while (++vc != done);
    for (std::uint32_t x : ends) {
        m_mesh.search_segment(v, x, m_p.edge_threshold, m_near);
        for (const auto& [d, w] : m_near)
            if (d < m_p.edge_threshold) push(d, Kind::edge, w, std::min(v, x), std::max(v, x));
    }
}

// What an edit can create: pairs with the new vertex w or its edges (found from w, both ways),
// and new triangles around the vertices whose star changed (cases 1 and 3 live on triangles).
// Pairs between two untouched vertices existed before and are already queued; one that was
// dropped because a constraint hid it is found again by the next full scan.
void Snapper::after_edit(std::uint32_t w)
{
    std::vector<std::uint32_t> touched;
    touched.swap(m_touched);
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    discover(w);
    discover_edges_of(w);
    for (std::uint32_t x : touched) {
        if (x == w || !alive(x)) continue;
        if (x >= m_slots_before) { // a crossing vertex the edit created: as new as w
            discover(x);
            discover_edges_of(x);
        } else {
            discover_faces(x);
        }
    }
}

// A merge across a constraint would drag edges through it; such a pair always has a closer
// vertex-edge event (one of the two is within half their distance of the constraint).
bool Snapper::visible(std::uint32_t a, std::uint32_t b)
{
    const double d = dist(m_mesh.vertex(a), m_mesh.vertex(b));
    m_mesh.search_point(a, d, d, m_near, m_edges);
    const cdt::Point& pa = m_mesh.vertex(a).handle->point();
    const cdt::Point& pb = m_mesh.vertex(b).handle->point();
    const cdt::Segment ab(pa, pb);
    for (const auto& [dv, w] : m_near) {
        if (w == b) continue;
        const cdt::Point& pw = m_mesh.vertex(w).handle->point();
        if (CGAL::collinear(pa, pw, pb) && CGAL::collinear_are_strictly_ordered_along_line(pa, pw, pb)) return false;
    }
    for (const EdgeHit& h : m_edges) {
        if (h.b == b || h.c == b) continue;
        const cdt::Segment e(m_mesh.vertex(h.b).handle->point(), m_mesh.vertex(h.c).handle->point());
        if (CGAL::do_intersect(ab, e)) return false;
    }
    return true;
}

bool Snapper::apply_face(const Event& e)
{
    auto& tri = m_mesh.tri();
    if (!alive(e.a) || !alive(e.b) || !alive(e.c)) return false;
    const VertexRecord &ra = m_mesh.vertex(e.a), &rb = m_mesh.vertex(e.b), &rc = m_mesh.vertex(e.c);
    if (!tri.is_face(ra.handle, rb.handle, rc.handle)) return false;
    if (std::max({dist(ra, rb), dist(rb, rc), dist(rc, ra)}) > m_p.vertex_threshold) return false;
    const double w = ra.weight + rb.weight + rc.weight;
    const double x = (ra.weight * ra.x + rb.weight * rb.x + rc.weight * rc.x) / w;
    const double y = (ra.weight * ra.y + rb.weight * rb.y + rc.weight * rc.y) / w;
    const std::array<std::uint32_t, 3> olds{e.a, e.b, e.c};
    after_edit(m_mesh.replace(olds, x, y, nullptr, m_touched));
    m_out.merges += 2;
    return true;
}

bool Snapper::apply_merge(const Event& e)
{
    if (!alive(e.a) || !alive(e.b) || !visible(e.a, e.b)) return false;
    const VertexRecord &ra = m_mesh.vertex(e.a), &rb = m_mesh.vertex(e.b);
    const std::array<std::uint32_t, 2> olds{e.a, e.b};
    const double w = ra.weight + rb.weight;
    const double x = (ra.weight * ra.x + rb.weight * rb.x) / w, y = (ra.weight * ra.y + rb.weight * rb.y) / w;
    after_edit(m_mesh.replace(olds, x, y, nullptr, m_touched));
    m_out.merges += 1;
    return true;
}

bool Snapper::apply_split(const Event& e)
{
    if (!alive(e.a) || !alive(e.b) || !alive(e.c) || !m_mesh.is_constrained_edge(e.b, e.c)) return false;
    const VertexRecord &ra = m_mesh.vertex(e.a), &rb = m_mesh.vertex(e.b), &rc = m_mesh.vertex(e.c);
    if (e.kind == Kind::sliver && !m_mesh.tri().is_face(ra.handle, rb.handle, rc.handle)) return false;
    if (dist(ra, rb) <= m_p.vertex_threshold || dist(ra, rc) <= m_p.vertex_threshold) return false;
    m_mesh.owners_of_edge(e.b, e.c, m_owners);
    for (std::uint32_t o : m_owners) {
        if (std::count(ra.snapped_into.begin(), ra.snapped_into.end(), o) >= k_max_snaps_per_edge) {
            ++m_out.guarded;
            return false;
        }
    }
    const std::uint32_t split[2] = {e.b, e.c};
    const std::array<std::uint32_t, 1> olds{e.a};
    const std::uint32_t w = m_mesh.replace(olds, ra.x, ra.y, split, m_touched);
    m_mesh.note_snapped(w, m_owners); // replace() does not touch m_owners
    after_edit(w);
    m_out.splits += 1;
    return true;
}

bool Snapper::apply(const Event& e)
{
    switch (e.kind) {
    case Kind::face: return apply_face(e);
    case Kind::merge: return apply_merge(e);
    default: return apply_split(e);
    }
}

std::size_t Snapper::drain()
{
    std::size_t applied = 0;
    while (!m_queue.empty()) {
        if (m_ops >= m_p.max_operations) {
            m_out.converged = false;
            return applied;
        }
        const Event e = m_queue.top();
        m_queue.pop();
        m_touched.clear();
        m_slots_before = m_mesh.vertex_slots();
        if (apply(e)) ++applied, ++m_ops;
    }
    return applied;
}

// Whatever is still too close after the run: reported by the caller, never silently kept.
void Snapper::collect_unresolved()
{
    for (std::uint32_t v = 0; v < m_mesh.vertex_slots(); ++v) {
        if (!alive(v)) continue;
        m_mesh.search_point(v, m_p.vertex_threshold, m_p.edge_threshold, m_near, m_edges);
        const bool near_vertex = std::any_of(m_near.begin(), m_near.end(),
            [&](const auto& p) { return p.first < m_p.vertex_threshold; });
        const bool near_edge = std::any_of(m_edges.begin(), m_edges.end(),
            [&](const EdgeHit& h) { return h.d < m_p.edge_threshold; });
        if (near_vertex || near_edge) m_out.unresolved.push_back(v);
    }
}

SnapperOutcome Snapper::run()
{
    for (;;) {
        ++m_out.rounds;
        for (std::uint32_t v = 0; v < m_mesh.vertex_slots(); ++v)
            if (alive(v)) discover(v);
        const std::size_t applied = drain();
        if (applied == 0 || !m_out.converged) break;
    }
    if (!m_out.converged || m_out.guarded > 0) collect_unresolved();
    return m_out;
}

} // namespace

SnapperOutcome run_snapper(Mesh& mesh, const SnapperParams& params)
{
    return Snapper(mesh, params).run();
}

} // namespace trisnap::detail
