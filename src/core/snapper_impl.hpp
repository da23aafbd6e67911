#pragma once
// The snapper's insides, shared by snapper.cpp (the driver and the checks), snapper_discover.cpp
// (finding events) and snapper_apply.cpp (applying them). See snapper.hpp for the rules.
#include "core/snapper.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <unordered_set>
#include <vector>

namespace trisnap::detail {

enum class Kind : std::uint8_t { face = 1, merge = 2, sliver = 3, edge = 4 };

struct Event {
    double d2; ///< squared distance
    Kind kind;
    std::uint32_t a, b, c; ///< face: a<b<c; merge: a<b; sliver/edge: vertex a, edge b<c
    /// The queue's order: the whole event, a total order (d2 is never NaN).
    bool operator<(const Event& o) const
    {
        if (d2 != o.d2) {
            return d2 < o.d2;
        }
        return std::tie(kind, a, b, c) < std::tie(o.kind, o.a, o.b, o.c);
    }
};

/// A vertex without a face candidate (Snapper::m_face_key).
inline constexpr float k_no_face = std::numeric_limits<float>::infinity();

/// The smallest float >= d2 (d2 >= 0): the face candidates' keys in 4 bytes a vertex.
inline float rounded_up(double d2)
{
    if (!(d2 <= double{std::numeric_limits<float>::max()})) {
        return k_no_face;
    }
    const auto f = static_cast<float>(d2);
    return double{f} < d2 ? std::nextafter(f, k_no_face) : f;
}

/// The events in order, smallest first: a min-heap with four children a node.
///
/// The order is the whole event's (Event::operator<), a total order in which equal events are
/// the same event, so any heap pops the same sequence: the snapper's output does not depend on
/// how the heap is built. Four children halve a binary heap's depth. At a tolerance near the
/// layer's size most of the queue is stale (an edit kills the vertices of every trivial face
/// around it): NJ shore at 0.1 degrees queued 1.7 M face events for 129 k collapses, 870 k at
/// once, before the face candidates of Snapper::check_face (530 k, 412 k at once, with them),
/// and popping them was half of the run, most of it waiting for memory on the binary heap's 20
/// levels (std::priority_queue; perf put 83 % of it on one compare).
/// pop() takes the hole at the root down to a leaf along the smallest children, then lets the
/// last event rise from there (it belongs near the bottom), as libstdc++'s binary heap does.
class EventQueue {
public:
    bool empty() const { return m_heap.empty(); }
    std::size_t size() const { return m_heap.size(); }
    const Event& top() const { return m_heap.front(); }
    void clear() { m_heap.clear(); }

    void push(const Event& e)
    {
        m_heap.push_back(e);
        rise(m_heap.size() - 1, e);
    }

    void pop()
    {
        const Event last = m_heap.back();
        m_heap.pop_back();
        const std::size_t n = m_heap.size();
        if (n == 0) {
            return;
        }
        std::size_t hole = 0;
        for (;;) {
            const std::size_t first = 4 * hole + 1;
            if (first >= n) {
                break;
            }
            const std::size_t end = std::min(first + 4, n);
            std::size_t best = first;
            for (std::size_t k = first + 1; k < end; ++k) {
                if (m_heap[k] < m_heap[best]) {
                    best = k;
                }
            }
            m_heap[hole] = m_heap[best];
            hole = best;
        }
        rise(hole, last);
    }

private:
    /// Puts e at the hole i or above it, moving larger parents down.
    void rise(std::size_t i, const Event& e)
    {
        while (i > 0) {
            const std::size_t parent = (i - 1) / 4;
            if (!(e < m_heap[parent])) {
                break;
            }
            m_heap[i] = m_heap[parent];
            i = parent;
        }
        m_heap[i] = e;
    }

    std::vector<Event> m_heap;
};

/// A vertex's merge candidate: the pair with the smallest key (d2, then ids) among the pairs it
/// may still merge with (alive, within t, not parked this round); `other` is none when it has none.
/// The pair's d2 is not kept: Mesh::vertex_d2 gives it again, bit for bit (4 bytes a vertex
/// instead of 16: 20 MB of Andorra x43's untiled peak).
struct MergeCandidate {
    static constexpr std::uint32_t none = UINT32_MAX;
    std::uint32_t other = none;
};
static_assert(sizeof(MergeCandidate) == 4);

class Snapper {
public:
    Snapper(Mesh& mesh, const SnapperParams& p, WorkMeter* meter);
    SnapperOutcome run();

private:
    // snapper_discover.cpp
    void initial_scan(bool every_pair);
    void discover_point(std::uint32_t v, bool every_pair);
    bool register_nearest(std::uint32_t v);
    void find_candidate(std::uint32_t v);
    void merge_event_gone(const Event& e);
    void discover_segment(std::uint32_t b, std::uint32_t c);
    void check_face(cdt::Face_handle f, bool every_face);
    bool collapse_event(std::array<std::uint32_t, 3> ids, Event& out) const;
    void face_event_gone(const Event& e);
    void find_face_candidate(std::uint32_t v);
    void check_changed_faces();
    void after_edit(std::uint32_t w);
    // snapper_apply.cpp
    bool apply(const Event& e);
    bool applicable(const Event& e, bool count_guard);
    bool apply_face(const Event& e);
    bool apply_merge(const Event& e);
    bool apply_split(const Event& e);
    bool visible(std::uint32_t a, std::uint32_t b);
    bool guard_allows(std::uint32_t v, std::uint32_t b, std::uint32_t c, bool count_guard);
    // snapper.cpp
    std::size_t drain();
    bool retry_parked();
    std::size_t count_misses();
    void collect_unresolved();

    void push(double d2, Kind k, std::uint32_t a, std::uint32_t b, std::uint32_t c)
    {
        m_queue.push(Event{d2, k, a, b, c});
        m_out.face_events += k == Kind::face ? 1 : 0;
        m_out.peak_queue = std::max(m_out.peak_queue, m_queue.size());
    }
    bool alive(std::uint32_t v) const { return m_mesh.alive(v); }
    /// Squared length below which a constrained edge can give no split event (discover_segment).
    double long_edge2() const { return 0.98 * 4 * (m_vt2 - m_et2) - 1e-12 * m_vt2; }
    double dist2(std::uint32_t p, std::uint32_t q) const { return m_mesh.vertex_d2(p, q); }

    Mesh& m_mesh;
    SnapperParams m_p;
    double m_vt2;     ///< squared thresholds
    double m_et2;
    double m_st2;
    SnapperOutcome m_out;
    WorkMeter* m_meter;
    EventQueue m_queue;
    std::vector<Event> m_parked;       ///< merges refused because a constraint lay between
    std::unordered_set<std::uint64_t> m_parked_pairs; ///< their pairs (edge_key), this round
    std::vector<MergeCandidate> m_candidate; ///< per vertex id (see discover_point)
    /// Per vertex id: the squared distance of its face candidate rounded up to a float, +inf for
    /// none (see check_face).
    std::vector<float> m_face_key;
    std::vector<void*> m_changed;      ///< faces CGAL created or changed since the last look
    std::vector<std::pair<double, std::uint32_t>> m_near;
    std::vector<EdgeHit> m_edges;
    std::vector<std::uint32_t> m_owners;
    std::size_t m_ops = 0;
};

} // namespace trisnap::detail
