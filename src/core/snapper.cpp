// The driver: one scan, then the queue drained with local re-discovery after every edit, parked
// merges tried again until none goes through (see snapper.hpp).
#include "core/snapper_impl.hpp"

#include "core/tracked_face.hpp"

#include <algorithm>
#include <tuple>
#include <utility>

namespace trisnap::detail {

Snapper::Snapper(Mesh& mesh, const SnapperParams& p, WorkMeter* meter)
    : m_mesh(mesh), m_p(p), m_vt2(p.vertex_threshold * p.vertex_threshold),
      m_et2(p.edge_threshold * p.edge_threshold), m_st2(p.sliver_threshold * p.sliver_threshold), m_meter(meter)
{
}

std::size_t Snapper::drain()
{
    std::size_t applied = 0;
    std::size_t popped = 0;
    const std::size_t slots = m_mesh.vertex_slots();
    while (!m_queue.empty()) {
        if (m_ops >= m_p.max_operations) {
            m_out.converged = false;
            return applied;
        }
        const Event e = m_queue.top();
        m_queue.pop();
        // The second half of the step: the share of the queue seen so far (it can grow; the
        // meter reports only increases).
        if (m_meter && (++popped & 255) == 0) {
            m_meter->advance(slots + slots * popped / (popped + m_queue.size()), 2 * slots);
        }
        if (apply(e)) {
            ++applied;
            ++m_ops;
        }
    }
    return applied;
}

// Merges a constraint blocked: when one of them can go through now, they are queued again (the
// two vertices have not moved, so the distance is the one they were found at) and become their
// ends' candidates; nothing else is left to merge once the queue has drained.
bool Snapper::retry_parked()
{
    std::vector<Event> parked;
    parked.swap(m_parked);
    m_parked_pairs.clear();
    bool any = false;
    for (const Event& e : parked) {
        if (!alive(e.a) || !alive(e.b)) {
            continue;
        }
        m_queue.push(e);
        m_candidate[e.a] = MergeCandidate{};
        m_candidate[e.b] = MergeCandidate{};
        any = any || visible(e.a, e.b);
    }
    // Each end's smallest parked pair becomes its candidate: nothing else is left to merge.
    for (const Event& e : parked) {
        for (const auto& [x, other] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}}) {
            MergeCandidate& c = m_candidate[x];
            const bool smaller = c.other == MergeCandidate::none ||
                                 std::tie(e.d2, e.a, e.b) <
                                     std::make_tuple(m_mesh.vertex_d2(x, c.other), std::min(x, c.other), std::max(x, c.other));
            if (alive(e.a) && alive(e.b) && smaller) {
                c = MergeCandidate{other};
            }
        }
    }
    if (!any) { // nothing can go through: keep them parked, drop the re-queued copies
        m_queue.clear();
        for (const Event& e : parked) {
            if (alive(e.a) && alive(e.b)) {
                m_parked.push_back(e);
                m_parked_pairs.insert(edge_key(e.a, e.b));
            }
        }
    }
    return any;
}

// A full scan at the fix-point: every event a scan from scratch would find that apply() would
// still carry out. 0 when the local re-discovery missed nothing.
std::size_t Snapper::count_misses()
{
    initial_scan(true);
    std::size_t misses = 0;
    while (!m_queue.empty()) {
        const Event e = m_queue.top();
        m_queue.pop();
        if (applicable(e, false)) {
            ++misses;
        }
    }
    return misses;
}

// Whatever is still too close after the run: reported by the caller, never silently kept.
void Snapper::collect_unresolved()
{
    for (std::uint32_t v = 0; v < m_mesh.vertex_slots(); ++v) {
        if (!alive(v)) {
            continue;
        }
        m_mesh.search_point(v, m_vt2, m_et2, m_near, m_edges);
        const bool near_vertex = std::any_of(m_near.begin(), m_near.end(), [&](const auto& p) { return p.first < m_vt2; });
        const bool near_edge = std::any_of(m_edges.begin(), m_edges.end(), [&](const EdgeHit& h) { return h.d2 < m_et2; });
        if (near_vertex || near_edge) {
            m_out.unresolved.push_back(v);
        }
    }
}

SnapperOutcome Snapper::run()
{
    m_candidate.reserve(with_room(m_mesh.vertex_slots())); // room for the edits' vertices
    m_candidate.resize(m_mesh.vertex_slots());
    m_mesh.set_long_edge_length2(std::max(0.0, long_edge2()));
    initial_scan(false);
    const cdt::ChangedFaces tracking(m_changed);
    for (;;) {
        ++m_out.rounds;
        drain();
        if (!m_out.converged || !retry_parked()) {
            break;
        }
    }
    m_out.faces_visited += m_mesh.faces_walked();
    if (m_p.verify && m_out.converged) {
        m_out.fixpoint_misses = count_misses();
    }
    // Whatever may still be too close is looked for and reported (205/207), never kept
    // silently: after the cap, a refused split, or merges a constraint kept blocked to the end
    // (the argument in visible() says a closer split always frees them; this checks it).
    if (!m_out.converged || m_out.guarded > 0 || !m_parked.empty()) {
        collect_unresolved();
    }
    return m_out;
}

SnapperOutcome run_snapper(Mesh& mesh, const SnapperParams& params, WorkMeter* meter)
{
    if (meter) meter->begin(WorkMeter::Step::snapping);
    return Snapper(mesh, params, meter).run();
}

} // namespace trisnap::detail
