// Applying events: each re-checks its condition (the queue holds stale events too), then edits
// the mesh through Mesh::replace().
#include "core/snapper_impl.hpp"

#include <algorithm>
#include <array>

namespace trisnap::detail {
namespace {

// How often one vertex may be split into the same input edge. Once is enough on real layers;
// on dense overlapping synthetic tangles a vertex dragged off an edge by later merges can need a
// second or third split, and refusing left vertices at 0.28 t from edges. The bound keeps the
// termination argument (finitely many splits per vertex and edge).
constexpr std::ptrdiff_t k_max_snaps_per_edge = 4;

} // namespace

// A merge across a constraint would drag edges through it; such a pair always has a closer
// vertex-edge event (one of the two is within half their distance of the constraint). A vertex
// inside the segment blocks it too (that pair is closer). Constraints at a or b do not count.
bool Snapper::visible(std::uint32_t a, std::uint32_t b)
{
    return m_mesh.segment_is_free(a, b);
}

bool Snapper::guard_allows(std::uint32_t v, std::uint32_t b, std::uint32_t c, bool count_guard)
{
    const std::vector<std::uint32_t>& into = m_mesh.snapped_into(v);
    m_mesh.owners_of_edge(b, c, m_owners);
    for (std::uint32_t o : m_owners) {
        if (std::count(into.begin(), into.end(), o) >= k_max_snaps_per_edge) {
            if (count_guard) {
                ++m_out.guarded;
            }
            return false;
        }
    }
    return true;
}

// The event's condition as apply() checks it, without editing anything. `count_guard`: count a
// split the repeated-split guard refuses.
bool Snapper::applicable(const Event& e, bool count_guard)
{
    const auto& tri = m_mesh.tri();
    switch (e.kind) {
    case Kind::face: {
        if (!alive(e.a) || !alive(e.b) || !alive(e.c)) {
            return false;
        }
        if (!tri.is_face(m_mesh.handle(e.a), m_mesh.handle(e.b), m_mesh.handle(e.c))) {
            return false;
        }
        return std::max({dist2(e.a, e.b), dist2(e.b, e.c), dist2(e.c, e.a)}) <= m_vt2;
    }
    case Kind::merge:
        return alive(e.a) && alive(e.b) && visible(e.a, e.b);
    default:
        break;
    }
    if (!alive(e.a) || !alive(e.b) || !alive(e.c) || !m_mesh.is_constrained_edge(e.b, e.c)) {
        return false;
    }
    if (e.kind == Kind::sliver &&
        !tri.is_face(m_mesh.handle(e.a), m_mesh.handle(e.b), m_mesh.handle(e.c))) {
        return false;
    }
    if (dist2(e.a, e.b) <= m_vt2 || dist2(e.a, e.c) <= m_vt2) {
        return false;
    }
    return guard_allows(e.a, e.b, e.c, count_guard);
}

bool Snapper::apply_face(const Event& e)
{
    if (!applicable(e, true)) {
        face_event_gone(e);
        return false;
    }
    const VertexRecord ra = m_mesh.vertex(e.a);
    const VertexRecord rb = m_mesh.vertex(e.b);
    const VertexRecord rc = m_mesh.vertex(e.c);
    const double wa = ra.weight, wb = rb.weight, wc = rc.weight;
    const double w = wa + wb + wc;
    const double x = (wa * ra.x + wb * rb.x + wc * rc.x) / w;
    const double y = (wa * ra.y + wb * rb.y + wc * rc.y) / w;
    const std::array<std::uint32_t, 3> olds{e.a, e.b, e.c};
    after_edit(m_mesh.replace(olds, x, y, nullptr));
    m_out.merges += 2;
    return true;
}

bool Snapper::apply_merge(const Event& e)
{
    if (!alive(e.a) || !alive(e.b) || m_parked_pairs.count(edge_key(e.a, e.b)) != 0) {
        merge_event_gone(e);
        return false;
    }
    if (!visible(e.a, e.b)) {
        m_parked.push_back(e);
        m_parked_pairs.insert(edge_key(e.a, e.b));
        merge_event_gone(e);
        return false;
    }
    const VertexRecord ra = m_mesh.vertex(e.a);
    const VertexRecord rb = m_mesh.vertex(e.b);
    const std::array<std::uint32_t, 2> olds{e.a, e.b};
    const double wa = ra.weight, wb = rb.weight;
    const double w = wa + wb;
    const double x = (wa * ra.x + wb * rb.x) / w;
    const double y = (wa * ra.y + wb * rb.y) / w;
    after_edit(m_mesh.replace(olds, x, y, nullptr));
    m_out.merges += 1;
    return true;
}

bool Snapper::apply_split(const Event& e)
{
    if (!applicable(e, true)) {
        return false;
    }
    const VertexRecord ra = m_mesh.vertex(e.a);
    const std::uint32_t split[2] = {e.b, e.c};
    const std::array<std::uint32_t, 1> olds{e.a};
    const std::uint32_t w = m_mesh.replace(olds, ra.x, ra.y, split);
    m_mesh.note_snapped(w, m_owners); // m_owners: the owners guard_allows() looked up
    after_edit(w);
    m_out.splits += 1;
    return true;
}

bool Snapper::apply(const Event& e)
{
    switch (e.kind) {
    case Kind::face:
        return apply_face(e);
    case Kind::merge:
        return apply_merge(e);
    default:
        return apply_split(e);
    }
}

} // namespace trisnap::detail
