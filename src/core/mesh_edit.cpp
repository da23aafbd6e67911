// Moving and merging vertices of the constrained triangulation. CGAL 5.5 has no "move a
// constrained vertex" (move_if_no_collision drops constraints; the inherited
// remove_incident_constraints corrupts Constrained_triangulation_plus_2's hierarchy), so an edit
// removes every constraint through the old vertices one by one with remove_constraint, removes
// the vertices, inserts the new point and re-inserts the constraints as single edges with their
// owners. Zero-length pieces vanish; duplicates stay as two contexts on one sub-edge (their
// owners are merged that way, and odd-even parity stays right).
#include "core/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace trisnap::detail {

void Mesh::one_ring(cdt::Vertex_handle h, std::vector<std::uint32_t>& out) const
{
    auto vc = m_tri.incident_vertices(h), done = vc;
    if (vc == nullptr) return;
    do {
        if (!m_tri.is_infinite(vc) && vc->info().id != cdt::k_no_id) out.push_back(vc->info().id);
    } while (++vc != done);
}

void Mesh::collect_constraints(cdt::Vertex_handle h, std::vector<Saved>& saved,
                               std::vector<std::uint32_t>& touched)
{
    one_ring(h, touched);
    std::vector<cdt::Constraint_id> cids;
    auto ec = m_tri.incident_edges(h), done = ec;
    if (ec == nullptr) return;
    do {
        const cdt::Face_handle f = ec->first;
        const int i = ec->second;
        if (m_tri.is_infinite(*ec) || !f->is_constrained(i)) continue;
        const auto a = f->vertex(m_tri.cw(i)), b = f->vertex(m_tri.ccw(i));
        for (auto it = m_tri.contexts_begin(a, b); it != m_tri.contexts_end(a, b); ++it)
            if (std::find(cids.begin(), cids.end(), it->id()) == cids.end()) cids.push_back(it->id());
    } while (++ec != done);
    for (const cdt::Constraint_id& cid : cids) {
        Saved s;
        s.list.assign(m_tri.vertices_in_constraint_begin(cid), m_tri.vertices_in_constraint_end(cid));
        s.owner = m_owner_of.at(cid);
        saved.push_back(std::move(s));
        m_owner_of.erase(cid);
        m_tri.remove_constraint(cid);
    }
}

cdt::Vertex_handle Mesh::insert_target(double x, double y, const std::uint32_t* split,
                                       cdt::Face_handle hint)
{
    if (split == nullptr) return m_tri.insert(cdt::Point(x, y), hint);
    // The exact foot of the perpendicular lies exactly on the constrained edge, so CGAL locates
    // it on that edge and splits the constraint there; a foot rounded to doubles would land in a
    // neighbouring face and split nothing.
    const cdt::Point& b = m_vertices[split[0]].handle->point();
    const cdt::Point& c = m_vertices[split[1]].handle->point();
    const cdt::Point foot = cdt::Kernel::Line_2(b, c).projection(cdt::Point(x, y));
    return m_tri.insert(foot, m_vertices[split[0]].handle->face());
}

void Mesh::merge_into(std::uint32_t target, std::span<const std::uint32_t> olds)
{
    VertexRecord& t = m_vertices[target];
    double zsum = std::isnan(t.z) ? 0.0 : t.z;
    int zn = std::isnan(t.z) ? 0 : 1;
    for (std::uint32_t o : olds) {
        if (o == target) continue;
        VertexRecord& r = m_vertices[o];
        if (!std::isnan(r.z)) zsum += r.z, ++zn;
        t.weight += r.weight;
        t.snapped_into.insert(t.snapped_into.end(), r.snapped_into.begin(), r.snapped_into.end());
        r.alive = false;
        r.handle = cdt::Vertex_handle();
        m_forward[o] = target;
    }
    t.z = zn ? zsum / zn : std::nan("");
}

void Mesh::reinsert(const std::vector<Saved>& saved, std::vector<std::uint32_t>& touched)
{
    std::vector<cdt::Vertex_handle> path;
    for (const Saved& s : saved) {
        path.clear();
        for (cdt::Vertex_handle h : s.list)
            if (path.empty() || path.back() != h) path.push_back(h);
        for (std::size_t i = 0; i + 1 < path.size(); ++i) {
            const cdt::Constraint_id cid = m_tri.insert_constraint(path[i], path[i + 1]);
            m_owner_of.emplace(cid, s.owner);
            for (auto it = m_tri.vertices_in_constraint_begin(cid); it != m_tri.vertices_in_constraint_end(cid); ++it) {
                if ((*it)->info().id != cdt::k_no_id) continue;
                touched.push_back(add_record(*it, interpolated_z(*it)));
                ++m_intersections;
            }
        }
    }
}

std::uint32_t Mesh::replace(std::span<const std::uint32_t> olds, double x, double y,
                            const std::uint32_t* split, std::vector<std::uint32_t>& touched)
{
    std::vector<Saved> saved;
    for (std::uint32_t o : olds) collect_constraints(m_vertices[o].handle, saved, touched);
    // Old vertices are referenced in `saved` by handle; they are replaced before re-insertion.
    std::vector<cdt::Vertex_handle> old_handles;
    for (std::uint32_t o : olds) old_handles.push_back(m_vertices[o].handle);
    for (cdt::Vertex_handle h : old_handles) {
        if (m_tri.are_there_incident_constraints(h))
            throw std::logic_error("trisnap: vertex still constrained after removing its constraints");
        m_tri.remove(h);
    }
    // Faces around the old vertices are gone: locate from a surviving neighbour.
    cdt::Face_handle hint;
    for (std::uint32_t t : touched)
        if (std::find(olds.begin(), olds.end(), t) == olds.end() && m_vertices[t].alive) {
            hint = m_vertices[t].handle->face();
            break;
        }
    // Handles of removed vertices are dangling: map them through their ids captured before.
    for (Saved& s : saved)
        for (cdt::Vertex_handle& h : s.list)
            for (std::size_t k = 0; k < olds.size(); ++k)
                if (h == old_handles[k]) h = cdt::Vertex_handle();
    const cdt::Vertex_handle target = insert_target(x, y, split, hint);
    std::uint32_t tid = target->info().id;
    if (tid == cdt::k_no_id) {
        tid = add_record(target, std::nan(""));
        m_vertices[tid].weight = 0; // a fresh point stands for nothing until the olds merge in
    }
    std::vector<std::uint32_t> sources(olds.begin(), olds.end());
    merge_into(tid, sources);
    if (split != nullptr) { // the moved vertex also takes the z the edge has there
        const VertexRecord &b = m_vertices[split[0]], &c = m_vertices[split[1]];
        const VertexRecord& t = m_vertices[tid];
        const double lb = std::hypot(t.x - b.x, t.y - b.y), lc = std::hypot(t.x - c.x, t.y - c.y);
        const double ze = lb + lc > 0 ? b.z + (c.z - b.z) * lb / (lb + lc) : b.z;
        if (!std::isnan(ze)) m_vertices[tid].z = std::isnan(t.z) ? ze : 0.5 * (t.z + ze);
    }
    for (Saved& s : saved)
        for (cdt::Vertex_handle& h : s.list)
            if (h == cdt::Vertex_handle()) h = target;
    reinsert(saved, touched);
    one_ring(target, touched);
    std::erase_if(touched, [&](std::uint32_t id) { return !m_vertices[id].alive; });
    return tid;
}

void Mesh::note_snapped(std::uint32_t v, const std::vector<std::uint32_t>& owners)
{
    auto& into = m_vertices[v].snapped_into;
    into.insert(into.end(), owners.begin(), owners.end());
}

} // namespace trisnap::detail
