// Separations of the output, over its distinct coordinates and distinct segments of all
// features together (a shared boundary is one set of segments, not two):
//  - vertex-vertex: per distinct vertex, its nearest other distinct vertex (STR tree);
//  - vertex-edge: per distinct vertex, its nearest segment it is not an endpoint of;
// the k closest of each, the exact minimum, and every breach (a vertex closer than T to another
// vertex, or than T/2 to an edge) with the snap report's excuse when it has one.
#include "assess/distinct.hpp"

#include <tbb/parallel_for.h>

#include <functional>

namespace trisnap::assess {
namespace {

/// A pair found by a nearest query: (distance, vertex, other vertex or segment).
struct Candidate {
    double d;
    std::uint32_t i, j;
    bool operator<(const Candidate& o) const { return d < o.d || (d == o.d && (i < o.i || (i == o.i && j < o.j))); }
    bool operator==(const Candidate& o) const { return i == o.i && j == o.j; }
};

/// The k smallest candidates one thread has seen, and the distance a query must beat to matter.
/// A thread's k-th best is never below the final k-th best, so pruning queries with it keeps
/// every candidate of the final list: the result does not depend on threads.
class TopK {
public:
    explicit TopK(std::size_t k = 20) : m_k(k) {}
    double bound() const { return m_bound == k_inf ? k_inf : std::nextafter(m_bound, k_inf); }
    void add(Candidate c)
    {
        m_items.push_back(c);
        if (m_items.size() >= 2 * m_k + 32) {
            trim();
        }
    }
    void trim()
    {
        std::sort(m_items.begin(), m_items.end());
        m_items.erase(std::unique(m_items.begin(), m_items.end()), m_items.end());
        if (m_items.size() > m_k) {
            m_items.resize(m_k);
        }
        if (m_items.size() == m_k) {
            m_bound = m_items.back().d;
        }
    }
    std::vector<Candidate> m_items;

private:
    std::size_t m_k;
    double m_bound = k_inf;
};

std::vector<Candidate> merge(tbb::combinable<TopK>& per_thread, std::size_t k)
{
    TopK all(k);
    per_thread.combine_each([&](TopK& t) {
        for (const Candidate& c : t.m_items) {
            all.add(c);
        }
    });
    all.trim();
    return all.m_items;
}

/// One thread's breaches: vertices counted, those the report explains, and their examples.
struct Breaches {
    std::int64_t count = 0;
    std::int64_t excused = 0;
    std::vector<AssessExample> examples;
};

/// Per vertex (not per pair): a pair of vertices closer than T is two breaches.
void note_breach(const Context& c, Breaches& b, const AssessExample& pair)
{
    ++b.count;
    const std::string why = c.excuses.explain_separation({pair.x, pair.y}, {pair.x2, pair.y2}, c.tolerance);
    if (why.empty()) {
        return;
    }
    ++b.excused;
    AssessExample e = pair;
    e.excused_by = why;
    push_bounded(b.examples, std::move(e), c.k, by_fids);
}

std::int64_t merge_breaches(tbb::combinable<Breaches>& per_thread, AssessReport& r)
{
    std::int64_t count = 0;
    per_thread.combine_each([&](const Breaches& b) {
        count += b.count;
        r.excused_counts.separations += b.excused;
        r.excused.insert(r.excused.end(), b.examples.begin(), b.examples.end());
    });
    return count;
}

/// The snap report's excuse on the closest pairs that breach.
void explain_closest(const Context& c, std::vector<AssessExample>& closest, double limit)
{
    for (AssessExample& e : closest) {
        if (e.value < limit) {
            e.excused_by = c.excuses.explain_separation({e.x, e.y}, {e.x2, e.y2}, c.tolerance);
        }
    }
}

void vertex_vertex(const Context& c, const std::vector<Owned>& v, AssessReport& r)
{
    std::vector<Box> boxes(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        boxes[i].add(v[i].p);
    }
    const StrTree tree(std::move(boxes));
    const double t = c.tolerance;
    const auto fid = [&](std::uint32_t i) { return c.b.features[v[i].feature].fid; };
    tbb::combinable<TopK> found([&c] { return TopK(c.k); });
    tbb::combinable<Breaches> breaches;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(v.size()), 1024), [&](const auto& range) {
        TopK& mine = found.local();
        for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            const auto [j, dist] = tree.nearest(
                p, [&](std::uint32_t id) { return id == i ? k_inf : distance(p, v[id].p); }, std::max(mine.bound(), t));
            if (j == UINT32_MAX) {
                continue;
            }
            mine.add({dist, std::min(i, j), std::max(i, j)});
            if (dist < t) {
                note_breach(c, breaches.local(), pair_example(fid(i), fid(j), p, v[j].p, dist, "vertex-vertex"));
            }
        }
    });
    r.n_vv_breaches = merge_breaches(breaches, r);
    for (const Candidate& k : merge(found, c.k)) {
        r.closest_vertex_vertex.push_back(pair_example(fid(k.i), fid(k.j), v[k.i].p, v[k.j].p, k.d));
    }
    explain_closest(c, r.closest_vertex_vertex, t);
    if (!r.closest_vertex_vertex.empty()) {
        r.min_vertex_vertex = r.closest_vertex_vertex.front().value;
    }
}

/// Per distinct vertex, its nearest segment that does not end at it.
void vertex_edge(const Context& c, const std::vector<Owned>& v, const DistinctSegments& d, AssessReport& r)
{
    const std::vector<Segment>& s = d.segments;
    const double limit = c.tolerance / 2;
    tbb::combinable<TopK> found([&c] { return TopK(c.k); });
    tbb::combinable<Breaches> breaches;
    const auto example = [&](std::uint32_t i, std::uint32_t j, double dist) {
        const Pt p = v[i].p;
        Pt closest;
        point_segment_distance(p, s[j].a, s[j].b, &closest);
        AssessExample e = pair_example(c.b.features[v[i].feature].fid, c.b.features[s[j].feature].fid, p, closest, dist,
                                       "vertex-edge");
        e.edge = {s[j].a.x, s[j].a.y, s[j].b.x, s[j].b.y};
        return e;
    };
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(v.size()), 1024), [&](const auto& range) {
        TopK& mine = found.local();
        for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            const auto dist_to = [&](std::uint32_t id) {
                return s[id].a == p || s[id].b == p ? k_inf : point_segment_distance(p, s[id].a, s[id].b);
            };
            const auto [j, dist] = d.tree.nearest(p, dist_to, std::max(mine.bound(), limit));
            if (j == UINT32_MAX) {
                continue;
            }
            mine.add({dist, i, j});
            if (dist < limit) {
                note_breach(c, breaches.local(), example(i, j, dist));
            }
        }
    });
    r.n_ve_breaches = merge_breaches(breaches, r);
    for (const Candidate& k : merge(found, c.k)) {
        r.closest_vertex_edge.push_back(example(k.i, k.j, k.d));
        r.closest_vertex_edge.back().text.clear();
    }
    explain_closest(c, r.closest_vertex_edge, limit);
    if (!r.closest_vertex_edge.empty()) {
        r.min_vertex_edge = r.closest_vertex_edge.front().value;
    }
}

} // namespace

void measure_separations(const Context& c, AssessReport& report)
{
    const std::vector<Owned> vertices = distinct_vertices(c.b);
    const DistinctSegments segments = distinct_segments(c.b);
    vertex_vertex(c, vertices, report);
    vertex_edge(c, vertices, segments, report);
    measure_crossings(c, segments, report);
}

} // namespace trisnap::assess
