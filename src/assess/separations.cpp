// Separations and crossings of the output: over distinct coordinates and distinct segments of
// all features together (a shared boundary is one set of segments, not two).
//  - min vertex-vertex: per distinct vertex, its nearest other distinct vertex (STR tree);
//  - min vertex-edge: per distinct vertex, its nearest segment it is not an endpoint of;
//  - crossings: per segment, the segments whose boxes meet it, classified exactly.
#include "assess/measures.hpp"
#include "assess/str_tree.hpp"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <functional>
#include <tuple>

namespace trisnap::assess {
namespace {

struct Owned {
    Pt p;
    std::uint32_t feature;
};
struct Segment {
    Pt a, b; // a < b
    std::uint32_t feature;
};

/// Distinct vertices, each with the first feature (lowest index) that has it.
std::vector<Owned> distinct_vertices(const LayerData& d)
{
    std::vector<Owned> v;
    v.reserve(d.pts.size());
    for (std::uint32_t f = 0; f < d.features.size(); ++f)
        for (std::uint32_t i = d.features[f].part_begin; i < d.features[f].part_end; ++i)
            for (std::uint32_t k = d.parts[i].begin; k < d.parts[i].end; ++k) v.push_back({d.pts[k], f});
    std::sort(v.begin(), v.end(), [](const Owned& x, const Owned& y) {
        return x.p < y.p || (x.p == y.p && x.feature < y.feature);
    });
    v.erase(std::unique(v.begin(), v.end(), [](const Owned& x, const Owned& y) { return x.p == y.p; }), v.end());
    return v;
}

/// Distinct non-degenerate segments (undirected), each with the first feature that has it.
std::vector<Segment> distinct_segments(const LayerData& d)
{
    std::vector<Segment> s;
    s.reserve(d.pts.size());
    for (std::uint32_t f = 0; f < d.features.size(); ++f)
        for (std::uint32_t i = d.features[f].part_begin; i < d.features[f].part_end; ++i)
            for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k) {
                const Pt p = d.pts[k], q = d.pts[k + 1];
                if (p != q) s.push_back({std::min(p, q), std::max(p, q), f});
            }
    std::sort(s.begin(), s.end(), [](const Segment& x, const Segment& y) {
        if (x.a != y.a) return x.a < y.a;
        if (x.b != y.b) return x.b < y.b;
        return x.feature < y.feature;
    });
    s.erase(std::unique(s.begin(), s.end(), [](const Segment& x, const Segment& y) { return x.a == y.a && x.b == y.b; }),
            s.end());
    return s;
}

using Examples = tbb::combinable<std::vector<AssessExample>>;

std::vector<AssessExample> gather(Examples& per_thread)
{
    std::vector<AssessExample> all;
    per_thread.combine_each([&](const std::vector<AssessExample>& v) { all.insert(all.end(), v.begin(), v.end()); });
    return all;
}

/// Keeps, per thread, only the k best so memory stays bounded on huge layers.
template <class Less>
void push_bounded(std::vector<AssessExample>& v, AssessExample e, std::size_t k, Less less)
{
    v.push_back(std::move(e));
    if (v.size() >= 4 * k + 64) keep_first(v, k, less);
}

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
        if (m_items.size() >= 2 * m_k + 32) trim();
    }
    void trim()
    {
        std::sort(m_items.begin(), m_items.end());
        m_items.erase(std::unique(m_items.begin(), m_items.end()), m_items.end());
        if (m_items.size() > m_k) m_items.resize(m_k);
        if (m_items.size() == m_k) m_bound = m_items.back().d;
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
        for (const Candidate& c : t.m_items) all.add(c);
    });
    all.trim();
    return all.m_items;
}

/// Per distinct vertex, its nearest other vertex; the k closest such pairs (the first is the
/// exact minimum over all pairs).
void vertex_vertex(const LayerData& d, const std::vector<Owned>& v, AssessReport& r, std::size_t k)
{
    std::vector<Box> boxes(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) boxes[i].add(v[i].p);
    const StrTree tree(std::move(boxes));
    tbb::combinable<TopK> found([k] { return TopK(k); });
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(v.size()), 1024), [&](const auto& range) {
        TopK& mine = found.local();
        for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            const auto [j, dist] = tree.nearest(
                p, [&](std::uint32_t id) { return id == i ? k_inf : distance(p, v[id].p); }, mine.bound());
            if (j != UINT32_MAX) mine.add({dist, std::min(i, j), std::max(i, j)});
        }
    });
    for (const Candidate& c : merge(found, k))
        r.closest_vertex_vertex.push_back({d.features[v[c.i].feature].fid, d.features[v[c.j].feature].fid, v[c.i].p.x,
                                           v[c.i].p.y, v[c.j].p.x, v[c.j].p.y, c.d, "", {}});
    if (!r.closest_vertex_vertex.empty()) r.min_vertex_vertex = r.closest_vertex_vertex.front().value;
}

/// Per distinct vertex, its nearest segment that does not end at it; the k closest.
void vertex_edge(const LayerData& d, const std::vector<Owned>& v, const std::vector<Segment>& s, const StrTree& tree,
                 AssessReport& r, std::size_t k)
{
    tbb::combinable<TopK> found([k] { return TopK(k); });
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(v.size()), 1024), [&](const auto& range) {
        TopK& mine = found.local();
        for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            const auto [j, dist] = tree.nearest(
                p,
                [&](std::uint32_t id) {
                    return s[id].a == p || s[id].b == p ? k_inf : point_segment_distance(p, s[id].a, s[id].b);
                },
                mine.bound());
            if (j != UINT32_MAX) mine.add({dist, i, j});
        }
    });
    for (const Candidate& c : merge(found, k)) {
        const Pt p = v[c.i].p;
        const Segment& e = s[c.j];
        Pt closest;
        point_segment_distance(p, e.a, e.b, &closest);
        r.closest_vertex_edge.push_back({d.features[v[c.i].feature].fid, d.features[e.feature].fid, p.x, p.y, closest.x,
                                         closest.y, c.d, "", {e.a.x, e.a.y, e.b.x, e.b.y}});
    }
    if (!r.closest_vertex_edge.empty()) r.min_vertex_edge = r.closest_vertex_edge.front().value;
}

void crossings(const LayerData& d, const std::vector<Segment>& s, const StrTree& tree, AssessReport& r, std::size_t k)
{
    tbb::combinable<std::int64_t> count;
    Examples found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.size(), 1024), [&](const auto& range) {
        auto& mine = found.local();
        auto& n = count.local();
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            tree.query(tree.box(static_cast<std::uint32_t>(i)), [&](std::uint32_t j) {
                if (j <= i) return;
                Pt where;
                if (segment_contact(s[i].a, s[i].b, s[j].a, s[j].b, &where) != SegmentContact::crossing) return;
                ++n;
                std::int64_t fa = d.features[s[i].feature].fid, fb = d.features[s[j].feature].fid;
                if (fb < fa) std::swap(fa, fb);
                push_bounded(mine, {fa, fb, where.x, where.y, 0, 0, 0, "", {}}, k, by_fids);
            });
        }
    });
    r.n_crossings = count.combine(std::plus<>());
    std::vector<AssessExample> all = gather(found);
    keep_first(all, k, by_fids);
    r.crossings = std::move(all);
}

} // namespace

void measure_separations(const LayerData& b, AssessReport& report, std::size_t k)
{
    const std::vector<Owned> vertices = distinct_vertices(b);
    const std::vector<Segment> segments = distinct_segments(b);
    std::vector<Box> boxes(segments.size());
    for (std::size_t i = 0; i < segments.size(); ++i) boxes[i] = segment_box(segments[i].a, segments[i].b);
    const StrTree tree(std::move(boxes));
    vertex_vertex(b, vertices, report, k);
    vertex_edge(b, vertices, segments, tree, report, k);
    crossings(b, segments, tree, report, k);
}

} // namespace trisnap::assess
