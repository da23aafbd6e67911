// Finding events: once everywhere at the start, then only where an edit changed something.
#include "core/snapper_impl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>

namespace trisnap::detail {

void Snapper::initial_scan(bool every_pair)
{
    const std::size_t slots = m_mesh.vertex_slots();
    // One pass over the faces: each face's own events (cases 1 and 3), and which vertices a
    // search could find anything from. A vertex's search (Mesh::search_point) walks the faces
    // around it, then crosses an edge of that star only where the edge meets the disk of radius
    // R = max(t, e) around it; it finds nothing while every edge opposite it in its faces is
    // farther than R (then so are the star's vertices, the ends of those edges).
    // Such a vertex, which is most vertices at a tolerance below the layer's detail, has no
    // event and no merge candidate, and its search is skipped: the same events are queued (their
    // order is their key's), and the snapper's work counter (faces_visited) no longer counts
    // those stars. The distances are those the search computes, from the same face in the same
    // order (and -ffp-contract=off), so they are the search's own; the margin (64 ulps of the
    // largest coordinate, Mesh::ulp_margin) would keep the skip clear of rounding all the same.
    // The verifying scan (every_pair) searches from every vertex.
    std::vector<std::uint8_t> searched(slots, every_pair ? 1 : 0);
    const double reach = std::sqrt(std::max(m_vt2, m_et2)) + m_mesh.ulp_margin();
    const double reach2 = reach * reach;
    for (const cdt::Face_handle f : m_mesh.tri().finite_face_handles()) {
        check_face(f, every_pair);
        if (every_pair) {
            continue;
        }
        const std::array<std::uint32_t, 3> ids{f->vertex(0)->info().id, f->vertex(1)->info().id,
                                               f->vertex(2)->info().id};
        for (int i = 0; i < 3; ++i) {
            const cdt::Point& rv = f->vertex(i)->point();
            const cdt::Point& ra = f->vertex(cdt::Triangulation::cw(i))->point();
            const cdt::Point& rb = f->vertex(cdt::Triangulation::ccw(i))->point();
            if (squared_distance_point_segment(rv.x(), rv.y(), ra.x(), ra.y(), rb.x(), rb.y()) <= reach2) {
                searched[ids[i]] = 1;
            }
        }
    }
    for (std::uint32_t v = 0; v < slots; ++v) {
        if (searched[v] != 0 && alive(v)) {
            discover_point(v, every_pair);
        }
        if (m_meter && (v & 1023) == 1023) {
            m_meter->advance(v, 2 * slots);
        }
    }
}

// Merges of v and splits of v into the constrained edges near it.
//
// Merges are not queued pair by pair: in a cluster where k vertices lie within t of each other
// that is k^2 events (Andorra at 0.01 degrees ran out of memory on them, and popping them was 3/4
// of the time at 0.001 degrees). Each vertex keeps one merge event in the queue, its candidate:
// the pair with the smallest key (d2, then ids) among those it may still merge with (alive,
// within t, not parked this round). Every such pair then has an event in the queue whose key is
// at most its own: its ends' candidates. A candidate that is popped while it still holds is the
// smallest of all pairs, so it is the merge the pair-by-pair queue would have popped there; one
// that no longer holds (an end merged away, or the pair was parked) makes its vertex look for
// its next candidate, whose key is at least the stale one. Hence the same merges in the same
// order, the same output, and a queue of O(vertices) events.
// `every_pair` (the verifying scan) queues every pair, seen from its lower end, as before.
void Snapper::discover_point(std::uint32_t v, bool every_pair)
{
    // One walk finds the edges within the edge threshold and the vertices within t, of which
    // only the nearest not parked with v matters (a full walk with parked pairs, the whole layer
    // per vertex at a tolerance near the layer's size, was most of CLC's 0.5-degree run).
    m_mesh.search_point(v, m_vt2, m_et2, m_near, m_edges, !every_pair,
                        m_parked_pairs.empty() ? nullptr : &m_parked_pairs);
    for (const EdgeHit& h : m_edges) {
        // Within t of an end of the edge the split is never applicable (it is left to the merge),
        // and the three vertices never move: such events are not queued.
        if (h.d2 < m_et2 && dist2(v, h.b) > m_vt2 && dist2(v, h.c) > m_vt2) {
            push(h.d2, Kind::edge, v, h.b, h.c);
        }
    }
    if (every_pair) {
        for (const auto& [d2, w] : m_near) {
            if (v < w) {
                push(d2, Kind::merge, v, w, 0);
            }
        }
        return;
    }
    register_nearest(v);
}

// Makes the smallest pair of v among m_near (parked pairs left out) its candidate, and queues it.
// Returns whether there was one.
bool Snapper::register_nearest(std::uint32_t v)
{
    if (m_candidate.size() <= v) {
        m_candidate.resize(m_mesh.vertex_slots());
    }
    m_candidate[v] = MergeCandidate{};
    bool found = false;
    std::tuple<double, std::uint32_t, std::uint32_t> best{};
    std::uint32_t other = MergeCandidate::none;
    for (const auto& [d2, w] : m_near) {
        if (!m_parked_pairs.empty() && m_parked_pairs.count(edge_key(v, w)) != 0) {
            continue;
        }
        const auto key = std::make_tuple(d2, std::min(v, w), std::max(v, w));
        if (!found || key < best) {
            found = true;
            best = key;
            other = w;
        }
    }
    if (found) {
        m_candidate[v] = MergeCandidate{other};
        push(std::get<0>(best), Kind::merge, std::min(v, other), std::max(v, other), 0);
    }
    return found;
}

// v's candidate died or was parked: its next one is the nearest vertex within t not parked
// with v, which the nearest-only walk finds without covering the disk (the search that grew
// from the stale distance out to t walked hundreds of vertices per call in a cluster).
void Snapper::find_candidate(std::uint32_t v)
{
    m_mesh.search_point(v, m_vt2, -1.0, m_near, m_edges, true, m_parked_pairs.empty() ? nullptr : &m_parked_pairs);
    register_nearest(v);
}

// A merge event that will not be applied (a vertex died, or the pair is parked): a live end whose
// candidate it was looks for its next one.
void Snapper::merge_event_gone(const Event& e)
{
    for (const auto& [x, other] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}}) {
        if (alive(x) && x < m_candidate.size() && m_candidate[x].other == other) {
            find_candidate(x);
        }
    }
}

// Vertices near a constrained edge the last edit inserted.
//
// Only a vertex w farther than t from both ends and nearer than the edge threshold e to b-c has
// an event here; the foot of w on b-c then lies more than sqrt(t^2 - e^2) from each end, so b-c
// is longer than 2 sqrt(t^2 - e^2) (sqrt(3) t at the default e = t/2). A shorter edge is not
// searched: the walk could find nothing to queue. At a tolerance larger than the features most
// new edges are short, and their capsule walks were 10-15 % of the run (JTS case 4 at 1223).
// The 0.98 and the 1e-12 t^2 keep the skip clear of the rounding of the squared distances
// (relative errors near 1e-16 of t^2), also when e is within rounding of t.
void Snapper::discover_segment(std::uint32_t b, std::uint32_t c)
{
    if (!alive(b) || !alive(c) || !m_mesh.is_constrained_edge(b, c)) {
        return;
    }
    if (dist2(b, c) < long_edge2()) {
        return;
    }
    m_mesh.search_segment(b, c, m_et2, m_near);
    for (const auto& [d2, w] : m_near) {
        if (d2 < m_et2 && dist2(w, b) > m_vt2 && dist2(w, c) > m_vt2) {
            push(d2, Kind::edge, w, std::min(b, c), std::max(b, c));
        }
    }
}

// Cases 1 and 3 are properties of one triangle: its three edges, and each vertex against the
// constrained edge opposite it.
//
// Face collapses are not queued face by face either (see discover_point for merges). At a
// tolerance near the layer's detail every edit leaves a star of trivial faces around its new
// vertex, and the next collapse kills most of them: NJ shore at 0.1 degrees queued 1.7 M face
// events for 129 k collapses, and popping the stale ones was a fifth of the run. Each vertex u
// keeps a face candidate instead: m_face_key[u] is the squared distance of the smallest face
// event queued for it, rounded up to a float (k_no_face: none). A trivial face is queued unless
// one of its vertices has a candidate with a smaller key (then it is covered), and lowers its
// vertices' candidates. When a face event is popped and does not apply, each live vertex whose
// candidate it was (same rounded key) searches its star for its smallest trivial face, which
// becomes its candidate. Why the same collapses happen in the same order: let f be the smallest
// event that applies. If f is not queued, it is covered by a vertex u whose candidate c is
// queued with c < f (a candidate changes only to a smaller one, or after a search to the
// smallest at u, which is f or smaller while f exists); c is popped first, does not apply (f is
// the smallest that does), and u's search then queues u's smallest trivial face, which is f (a
// smaller trivial face at u would apply, being one), before anything larger is popped. A
// candidate that applies kills all its vertices, and with them every face it covered. A queue
// that drains leaves no candidate behind (each was popped and either applied or was replaced by
// its vertex's next search), so parked merges' rounds start clean. The verifying scan queues
// every face (`every_face`).
void Snapper::check_face(cdt::Face_handle f, bool every_face)
{
    f->info().checked = true;
    std::array<std::uint32_t, 3> ids{f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id};
    if (m_st2 > 0) {
        for (int i = 0; i < 3; ++i) {
            if (!f->is_constrained(i)) {
                continue;
            }
            const cdt::Point& rv = f->vertex(i)->point();
            const std::uint32_t b = ids[cdt::Triangulation::cw(i)];
            const std::uint32_t c = ids[cdt::Triangulation::ccw(i)];
            const cdt::Point& rb = f->vertex(cdt::Triangulation::cw(i))->point();
            const cdt::Point& rc = f->vertex(cdt::Triangulation::ccw(i))->point();
            const double d2 = squared_distance_point_segment(rv.x(), rv.y(), rb.x(), rb.y(), rc.x(), rc.y());
            // Within t of an end of the edge the sliver is never applicable (applicable()
            // refuses it, and no vertex moves: an edit makes new ones), so it is not queued:
            // at a tolerance near the layer's size nearly every sliver found is such a one
            // (NJ shore at 0.1 degrees: 1.9 M queued for 4 applied).
            if (d2 <= m_st2 && dist2(ids[i], b) > m_vt2 && dist2(ids[i], c) > m_vt2) {
                push(d2, Kind::sliver, ids[i], std::min(b, c), std::max(b, c));
            }
        }
    }
    Event e{};
    if (!collapse_event(ids, e)) {
        return;
    }
    if (!every_face) {
        if (m_face_key.size() <= e.c) {
            m_face_key.resize(m_mesh.vertex_slots(), k_no_face);
        }
        if (std::any_of(ids.begin(), ids.end(), [&](std::uint32_t u) { return double{m_face_key[u]} < e.d2; })) {
            return; // covered by a candidate with a smaller key
        }
        const float key = rounded_up(e.d2);
        for (const std::uint32_t u : ids) {
            m_face_key[u] = std::min(m_face_key[u], key);
        }
    }
    push(e.d2, Kind::face, e.a, e.b, e.c);
}

// The face event of the triangle with these vertices when its three edges are all <= t.
bool Snapper::collapse_event(std::array<std::uint32_t, 3> ids, Event& out) const
{
    const double e0 = dist2(ids[0], ids[1]);
    const double e1 = dist2(ids[1], ids[2]);
    const double e2 = dist2(ids[2], ids[0]);
    if (std::max({e0, e1, e2}) > m_vt2) {
        return false;
    }
    std::sort(ids.begin(), ids.end());
    out = Event{std::min({e0, e1, e2}), Kind::face, ids[0], ids[1], ids[2]};
    return true;
}

// A face event popped that does not apply: each live vertex whose candidate it may have been
// (the same rounded key; another event of the same rounded key only costs a search) looks for
// its next one.
void Snapper::face_event_gone(const Event& e)
{
    const float key = rounded_up(e.d2);
    for (const std::uint32_t u : {e.a, e.b, e.c}) {
        if (alive(u) && u < m_face_key.size() && m_face_key[u] == key) {
            find_face_candidate(u);
        }
    }
}

// v's smallest trivial face by the queue's order becomes its candidate, and is queued.
void Snapper::find_face_candidate(std::uint32_t v)
{
    const auto& tri = m_mesh.tri();
    bool found = false;
    Event best{};
    auto fc = tri.incident_faces(m_mesh.handle(v));
    const auto done = fc;
    do {
        ++m_out.faces_visited;
        Event e{};
        if (!tri.is_infinite(fc) &&
            collapse_event({fc->vertex(0)->info().id, fc->vertex(1)->info().id, fc->vertex(2)->info().id}, e) &&
            (!found || e < best)) {
            found = true;
            best = e;
        }
    } while (++fc != done);
    m_face_key[v] = found ? rounded_up(best.d2) : k_no_face;
    if (found) {
        push(best.d2, Kind::face, best.a, best.b, best.c);
    }
}

// The faces CGAL created or changed during the last edit that still exist.
void Snapper::check_changed_faces()
{
    auto& faces = m_mesh.tri().tds().faces();
    for (void* p : m_changed) {
        auto& face = *static_cast<cdt::Tds::Face*>(p);
        const cdt::Face_handle f = cdt::Tds::Face_range::s_iterator_to(face);
        if (!faces.is_used(f) || f->info().checked || m_mesh.tri().is_infinite(f)) {
            continue;
        }
        check_face(f, false);
        ++m_out.faces_visited;
    }
    m_changed.clear();
}

// What an edit can make applicable: pairs with the new vertex and with the crossing vertices it
// created, vertices near the constrained edges it inserted, and the faces it changed.
void Snapper::after_edit(std::uint32_t w)
{
    discover_point(w, false);
    for (std::uint32_t x : m_mesh.last_created()) {
        if (alive(x)) {
            discover_point(x, false);
        }
    }
    for (const auto& [b, c] : m_mesh.last_new_edges()) {
        discover_segment(b, c);
    }
    check_changed_faces();
}

} // namespace trisnap::detail
