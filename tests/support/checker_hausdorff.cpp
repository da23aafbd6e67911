// Symmetric Hausdorff distance between each feature's input and output, computed on segments
// rather than on densified vertices (GEOS's densified Hausdorff is quadratic per feature, which
// a 44k-vertex polygon cannot afford). A segment pq is bisected only while an upper bound of
// the distance along it could beat the running maximum. Two bounds, take the smaller:
//  - the distance to the other side is 1-Lipschitz: at most (d(p) + d(q) + |pq|) / 2;
//  - the distance to one segment s is convex along pq, so at most max(d(p, s), d(q, s)) for s
//    the nearest segment of either end; this one goes to 0 where the sides coincide.
// Segments present unchanged in the other side are skipped (distance 0).
#include "checker_detail.hpp"
#include "checker_grid.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace trisnap::checker_detail {
namespace {

struct SegmentKey {
    std::uint32_t feature;
    double ax, ay, bx, by;
    friend bool operator<(const SegmentKey& l, const SegmentKey& r) {
        return std::tie(l.feature, l.ax, l.ay, l.bx, l.by) <
               std::tie(r.feature, r.ax, r.ay, r.bx, r.by);
    }
};

SegmentKey make_key(std::uint32_t feature, const Segment& s) {
    if (std::tie(s.bx, s.by) < std::tie(s.ax, s.ay))
        return SegmentKey{feature, s.bx, s.by, s.ax, s.ay};
    return SegmentKey{feature, s.ax, s.ay, s.bx, s.by};
}

std::vector<SegmentKey> segment_keys(const Side& side) {
    std::vector<SegmentKey> keys;
    keys.reserve(side.segments.size());
    for (const Segment& s : side.segments)
        keys.push_back(make_key(s.feature, s));
    std::sort(keys.begin(), keys.end());
    return keys;
}

struct Maximum {
    double value = 0.0;
    std::int64_t id = 0;
    double x = 0.0, y = 0.0;
};

/// Distances from the segments of one side (A) to the same feature on the other side (B).
class Directed {
public:
    Directed(const Side& a, const Side& b, double t, Maximum& max)
        : m_a(a), m_b(b), m_grid(b.segments, 2.0 * t), m_keys(segment_keys(b)), m_t(t),
          m_max(max) {}

    void vertices(std::size_t fa, std::size_t fb);
    void edges(std::size_t fa, std::size_t fb);

private:
    struct End {
        double x, y;
        Nearest nearest;
    };
    End measure(double x, double y);
    double bound(const End& p, const End& q) const;
    void bisect(const End& p, const End& q, int depth);

    const Side& m_a;
    const Side& m_b;
    SegmentGrid m_grid;
    std::vector<SegmentKey> m_keys;
    double m_t;
    Maximum& m_max;
    const SideFeature* m_target = nullptr; ///< the B feature of the pair being measured
};

Directed::End Directed::measure(double x, double y) {
    const Nearest n = m_grid.nearest_in_range(x, y, m_target->seg_begin, m_target->seg_end, m_t);
    if (n.distance > m_max.value)
        m_max = Maximum{n.distance, m_target->id, x, y};
    return End{x, y, n};
}

double Directed::bound(const End& p, const End& q) const {
    const double lipschitz =
        0.5 * (p.nearest.distance + q.nearest.distance + std::hypot(q.x - p.x, q.y - p.y));
    const Segment& sp = m_b.segments[p.nearest.index];
    const Segment& sq = m_b.segments[q.nearest.index];
    const double via_p = std::max(p.nearest.distance, point_segment_distance(q.x, q.y, sp));
    const double via_q = std::max(q.nearest.distance, point_segment_distance(p.x, p.y, sq));
    return std::min({lipschitz, via_p, via_q});
}

void Directed::vertices(std::size_t fa, std::size_t fb) {
    m_target = &m_b.features[fb];
    const SideFeature& f = m_a.features[fa];
    for (std::size_t i = f.seg_begin; i < f.seg_end; ++i) {
        measure(m_a.segments[i].ax, m_a.segments[i].ay);
        measure(m_a.segments[i].bx, m_a.segments[i].by);
    }
}

void Directed::edges(std::size_t fa, std::size_t fb) {
    m_target = &m_b.features[fb];
    const SideFeature& f = m_a.features[fa];
    for (std::size_t i = f.seg_begin; i < f.seg_end; ++i) {
        const Segment& s = m_a.segments[i];
        if (std::binary_search(m_keys.begin(), m_keys.end(),
                               make_key(static_cast<std::uint32_t>(fb), s)))
            continue;
        bisect(measure(s.ax, s.ay), measure(s.bx, s.by), 48);
    }
}

void Directed::bisect(const End& p, const End& q, int depth) {
    // A thousandth of t is well below anything the contract distinguishes.
    if (depth == 0 || bound(p, q) <= m_max.value + 1e-3 * m_t)
        return;
    const End mid = measure(0.5 * (p.x + q.x), 0.5 * (p.y + q.y));
    bisect(p, mid, depth - 1);
    bisect(mid, q, depth - 1);
}

/// (input index, output index) of every id with segments on both sides, in input order.
std::vector<std::pair<std::size_t, std::size_t>> matched(const Side& in, const Side& out,
                                                         const std::vector<std::int64_t>& exempt) {
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t i = 0; i < in.features.size(); ++i) {
        const SideFeature& f = in.features[i];
        auto it = out.by_id.find(f.id);
        if (std::find(exempt.begin(), exempt.end(), f.id) != exempt.end()) continue;
        if (f.seg_begin == f.seg_end || it == out.by_id.end())
            continue;
        const SideFeature& g = out.features[it->second];
        if (g.seg_begin != g.seg_end)
            pairs.emplace_back(i, it->second);
    }
    return pairs;
}

} // namespace

void measure_hausdorff(const Side& in, const Side& out, double t,
                       const std::vector<std::int64_t>& exempt, ContractReport& report,
                       Examples& examples) {
    Maximum max;
    Directed forward(in, out, t, max);
    Directed backward(out, in, t, max);
    const auto pairs = matched(in, out, exempt);
    // All vertices first: a high running maximum makes the bisection prune early.
    for (const auto& [i, o] : pairs) {
        forward.vertices(i, o);
        backward.vertices(o, i);
    }
    for (const auto& [i, o] : pairs) {
        forward.edges(i, o);
        backward.edges(o, i);
    }
    report.max_hausdorff = max.value;
    report.max_hausdorff_id = max.id;
    if (max.value > t)
        examples.add("hausdorff", "hausdorff " + distance_text(max.value, t) + ": id " +
                                      std::to_string(max.id) + " near " +
                                      point_text(max.x, max.y));
}

} // namespace trisnap::checker_detail
