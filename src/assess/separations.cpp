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

void vertex_vertex(const LayerData& d, const std::vector<Owned>& v, AssessReport& r, std::size_t k)
{
    std::vector<Box> boxes(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) boxes[i].add(v[i].p);
    const StrTree tree(std::move(boxes));
    std::vector<std::uint32_t> nearest(v.size(), UINT32_MAX);
    std::vector<double> dist(v.size(), k_inf);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, v.size(), 1024), [&](const auto& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            std::tie(nearest[i], dist[i]) =
                tree.nearest(p, [&](std::uint32_t id) { return id == i ? k_inf : distance(p, v[id].p); });
        }
    });
    std::vector<AssessExample> all;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::uint32_t j = nearest[i];
        if (j == UINT32_MAX || (j < i && nearest[j] == i)) continue; // a mutual pair, reported from j
        AssessExample e{d.features[v[i].feature].fid, d.features[v[j].feature].fid, v[i].p.x, v[i].p.y,
                        v[j].p.x, v[j].p.y, dist[i], "", {}};
        push_bounded(all, std::move(e), k, by_value);
    }
    keep_first(all, k, by_value);
    if (!all.empty()) r.min_vertex_vertex = all.front().value;
    r.closest_vertex_vertex = std::move(all);
}

void vertex_edge(const LayerData& d, const std::vector<Owned>& v, const std::vector<Segment>& s, const StrTree& tree,
                 AssessReport& r, std::size_t k)
{
    Examples found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, v.size(), 1024), [&](const auto& range) {
        auto& mine = found.local();
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            const Pt p = v[i].p;
            Pt closest;
            const auto [j, dist] = tree.nearest(p, [&](std::uint32_t id) {
                return s[id].a == p || s[id].b == p ? k_inf : point_segment_distance(p, s[id].a, s[id].b);
            });
            if (j == UINT32_MAX) continue;
            point_segment_distance(p, s[j].a, s[j].b, &closest);
            AssessExample e{d.features[v[i].feature].fid, d.features[s[j].feature].fid, p.x, p.y,
                            closest.x, closest.y, dist, "", {s[j].a.x, s[j].a.y, s[j].b.x, s[j].b.y}};
            push_bounded(mine, std::move(e), k, by_value);
        }
    });
    std::vector<AssessExample> all = gather(found);
    keep_first(all, k, by_value);
    if (!all.empty()) r.min_vertex_edge = all.front().value;
    r.closest_vertex_edge = std::move(all);
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
