// Finding events: once everywhere at the start, then only where an edit changed something.
#include "core/snapper_impl.hpp"

#include <algorithm>
#include <array>

namespace trisnap::detail {

void Snapper::initial_scan()
{
    const std::size_t slots = m_mesh.vertex_slots();
    for (std::uint32_t v = 0; v < slots; ++v) {
        if (alive(v)) {
            discover_point(v, true);
        }
        if (m_meter && (v & 1023) == 1023) {
            m_meter->advance(v, 2 * slots);
        }
    }
    for (const cdt::Face_handle f : m_mesh.tri().finite_face_handles()) {
        check_face(f);
    }
}

// Merges with the vertices near v and splits of v into the constrained edges near it. In the
// first scan every pair is seen from both ends, so only the end with the lower id pushes it.
void Snapper::discover_point(std::uint32_t v, bool only_higher)
{
    m_mesh.search_point(v, m_vt2, m_et2, m_near, m_edges);
    for (const auto& [d2, w] : m_near) {
        if (!only_higher || v < w) {
            push(d2, Kind::merge, std::min(v, w), std::max(v, w), 0);
        }
    }
    for (const EdgeHit& h : m_edges) {
        if (h.d2 < m_et2) {
            push(h.d2, Kind::edge, v, h.b, h.c);
        }
    }
}

// Vertices near a constrained edge the last edit inserted.
void Snapper::discover_segment(std::uint32_t b, std::uint32_t c)
{
    if (!alive(b) || !alive(c) || !m_mesh.is_constrained_edge(b, c)) {
        return;
    }
    m_mesh.search_segment(b, c, m_et2, m_near);
    for (const auto& [d2, w] : m_near) {
        if (d2 < m_et2) {
            push(d2, Kind::edge, w, std::min(b, c), std::max(b, c));
        }
    }
}

// Cases 1 and 3 are properties of one triangle: its three edges, and each vertex against the
// constrained edge opposite it.
void Snapper::check_face(cdt::Face_handle f)
{
    f->info().checked = true;
    std::array<std::uint32_t, 3> ids{f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id};
    if (m_st2 > 0) {
        for (int i = 0; i < 3; ++i) {
            if (!f->is_constrained(i)) {
                continue;
            }
            const VertexRecord& rv = m_mesh.vertex(ids[i]);
            const std::uint32_t b = ids[cdt::Triangulation::cw(i)];
            const std::uint32_t c = ids[cdt::Triangulation::ccw(i)];
            const VertexRecord& rb = m_mesh.vertex(b);
            const VertexRecord& rc = m_mesh.vertex(c);
            const double d2 = squared_distance_point_segment(rv.x, rv.y, rb.x, rb.y, rc.x, rc.y);
            if (d2 <= m_st2) {
                push(d2, Kind::sliver, ids[i], std::min(b, c), std::max(b, c));
            }
        }
    }
    const double e0 = dist2(ids[0], ids[1]);
    const double e1 = dist2(ids[1], ids[2]);
    const double e2 = dist2(ids[2], ids[0]);
    if (std::max({e0, e1, e2}) <= m_vt2) {
        std::sort(ids.begin(), ids.end());
        push(std::min({e0, e1, e2}), Kind::face, ids[0], ids[1], ids[2]);
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
        check_face(f);
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
