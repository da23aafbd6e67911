// Moving and merging vertices of the constrained triangulation. CGAL 5.5 has no "move a
// constrained vertex" (move_if_no_collision drops constraints), so an edit takes the owners of
// every constrained edge at the old vertices out of the owner table, removes the vertices,
// inserts the new point and re-inserts each edge from the new vertex to its other end with its
// owners (insert_segment: split at crossings and vertices on the way). An edge between two of
// the old vertices has length zero afterwards and vanishes; two edges that fold onto one keep
// both owners (odd-even parity stays right).
#include "core/exact.hpp"
#include "core/mesh.hpp"

#include <algorithm>
#include <cmath>

namespace trisnap::detail {

void Mesh::one_ring(cdt::Vertex_handle h, std::vector<std::uint32_t>& out) const
{
    auto vc = m_tri.incident_vertices(h);
    if (vc == nullptr) {
        return;
    }
    const auto done = vc;
    do {
        if (!m_tri.is_infinite(vc) && vc->info().id != cdt::k_no_id) {
            out.push_back(vc->info().id);
        }
    } while (++vc != done);
}

void Mesh::collect_constraints(cdt::Vertex_handle h, std::span<const std::uint32_t> olds)
{
    const std::size_t ring_start = m_ring.size();
    one_ring(h, m_ring);
    for (std::size_t k = ring_start; k < m_ring.size(); ++k) {
        const std::uint32_t n = m_ring[k];
        const auto first = static_cast<std::uint32_t>(m_arena.size());
        take_owners(id(h), n, m_arena);
        const auto count = static_cast<std::uint32_t>(m_arena.size() - first);
        if (count == 0) {
            continue;
        }
        if (std::find(olds.begin(), olds.end(), n) != olds.end()) {
            m_arena.resize(first); // between two old vertices: length zero after the edit
            continue;
        }
        m_saved.push_back(Saved{handle(n), first, count});
    }
    remove_incident_constraints_bounded(h);
}

cdt::Vertex_handle Mesh::insert_target(double x, double y, const std::uint32_t* split, cdt::Face_handle hint)
{
    if (split == nullptr) {
        return insert_point(cdt::Point(x, y), hint);
    }
    const cdt::Vertex_handle b = handle(split[0]);
    const cdt::Vertex_handle c = handle(split[1]);
    // The rounded foot lies within an ulp of b-c, not on it: b-c is routed through it explicitly
    // (it already is when the foot fell exactly on the edge and CGAL split it).
    const cdt::Vertex_handle v = insert_point(rounded_projection(cdt::Point(x, y), b->point(), c->point()), b->face());
    if (reroute(b, c, v)) {
        run_jobs();
    }
    return v;
}

void Mesh::merge_into(std::uint32_t target, std::span<const std::uint32_t> olds)
{
    VertexSlot& t = m_vertices[target];
    const double zt = z(target);
    double zsum = std::isnan(zt) ? 0.0 : zt;
    int zn = std::isnan(zt) ? 0 : 1;
    for (std::uint32_t o : olds) {
        if (o == target) {
            continue;
        }
        VertexSlot& r = m_vertices[o];
        if (const double zo = z(o); !std::isnan(zo)) {
            zsum += zo;
            ++zn;
        }
        t.weight += r.weight;
        if (r.snapped != cdt::k_no_id && !m_snapped[r.snapped].empty()) {
            if (t.snapped == cdt::k_no_id) { // before taking references into m_snapped
                t.snapped = static_cast<std::uint32_t>(m_snapped.size());
                m_snapped.emplace_back();
            }
            std::vector<std::uint32_t>& into = m_snapped[t.snapped];
            std::vector<std::uint32_t>& from = m_snapped[r.snapped];
            into.insert(into.end(), from.begin(), from.end());
            from.clear();
        }
        r.alive = false; // its point is in m_kept (replace() kept it before CGAL removed it)
        m_forward[o] = target;
    }
    set_z(target, zn ? zsum / zn : std::nan(""));
}

std::uint32_t Mesh::replace(std::span<const std::uint32_t> olds, double x, double y, const std::uint32_t* split)
{
    m_saved.clear();
    m_arena.clear();
    m_created.clear();
    m_new_edges.clear();
    m_ring.clear();
    for (std::uint32_t o : olds) {
        collect_constraints(handle(o), olds);
    }
    // The constraints go back in by the ids of their other ends, not in the order the stars were
    // walked: a star starts at whatever face CGAL keeps for the vertex, which depends on the
    // triangulation's history, and the crossings the re-inserted edges make get ids in the order
    // they are found. Those ids decide ties and sums later (a face's centroid adds its vertices
    // in id order), so Monaco at 5 m differed by one ulp between a tiled and an untiled run.
    std::stable_sort(m_saved.begin(), m_saved.end(),
                     [&](const Saved& p, const Saved& q) { return id(p.other) < id(q.other); });
    for (std::uint32_t o : olds) {
        const cdt::Vertex_handle h = handle(o);
        keep_point(o);
        remove_bounded(h);
    }
    // Faces around the old vertices are gone: locate from a surviving neighbour.
    cdt::Face_handle hint;
    for (std::uint32_t n : m_ring) {
        if (std::find(olds.begin(), olds.end(), n) == olds.end() && m_vertices[n].alive) {
            hint = handle(n)->face();
            break;
        }
    }
    const cdt::Vertex_handle target = insert_target(x, y, split, hint);
    const std::uint32_t tid = id(target);
    merge_into(tid, olds);
    if (split != nullptr) {
        take_edge_z(tid, split[0], split[1]);
    }
    // Pushed last to first, so they go in in the order they were collected.
    for (auto it = m_saved.rbegin(); it != m_saved.rend(); ++it) {
        push_job(target, it->other, it->first, it->count);
    }
    run_jobs();
    for (std::uint32_t c : m_created) {
        m_vertices[c].weight = 1;
        set_z(c, interpolated_z(handle(c)));
    }
    m_arena.clear();
    return tid;
}

// A vertex moved onto the edge b-c also takes the z the edge has there.
void Mesh::take_edge_z(std::uint32_t v, std::uint32_t b, std::uint32_t c)
{
    const Xy rb = xy(b);
    const Xy rc = xy(c);
    const Xy t = xy(v);
    const double lb = std::hypot(t.x - rb.x, t.y - rb.y);
    const double lc = std::hypot(t.x - rc.x, t.y - rc.y);
    const double zb = z(b);
    const double ze = lb + lc > 0 ? zb + (z(c) - zb) * lb / (lb + lc) : zb;
    if (!std::isnan(ze)) {
        const double zv = z(v);
        set_z(v, std::isnan(zv) ? ze : 0.5 * (zv + ze));
    }
}

void Mesh::note_snapped(std::uint32_t v, const std::vector<std::uint32_t>& owners)
{
    if (owners.empty()) {
        return;
    }
    std::uint32_t& list = m_vertices[v].snapped;
    if (list == cdt::k_no_id) {
        list = static_cast<std::uint32_t>(m_snapped.size());
        m_snapped.emplace_back();
    }
    std::vector<std::uint32_t>& into = m_snapped[list];
    into.insert(into.end(), owners.begin(), owners.end());
}

const std::vector<std::uint32_t>& Mesh::snapped_into(std::uint32_t v) const
{
    static const std::vector<std::uint32_t> none;
    const std::uint32_t list = m_vertices[v].snapped;
    return list == cdt::k_no_id ? none : m_snapped[list];
}

} // namespace trisnap::detail
