// Hausdorff distance per matched feature, between the input's and the output's boundaries (rings
// and lines), both directions. Computed exactly up to eps = T/1000 rather than by densifying
// (densifying at T would need 10^4 samples per edge on fine tolerances): along each edge s(t) of
// one side, f(t) = distance to the other side is bounded on [t0, t1] by
//  - 1-Lipschitz: f <= (f(t0) + f(t1) + length) / 2;
//  - convexity: the distance to one fixed segment is convex in t, so with g0, g1 the distances to
//    the nearest segments found at t0 and t1, f <= min(g0, g1) <= min of their chords;
// intervals whose bound cannot beat the best value found + eps are dropped, others are halved.
// The result is a lower bound within eps of the true distance.
#include "assess/measures.hpp"
#include "assess/str_tree.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>

namespace trisnap::assess {
namespace {

struct Seg {
    Pt a, b;
};

std::vector<Seg> segments_of(const LayerData& d, const Feature& f)
{
    std::vector<Seg> out;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        const Part& part = d.parts[i];
        if (part.end - part.begin == 1) {
            out.push_back({d.pts[part.begin], d.pts[part.begin]});
        }
        for (std::uint32_t k = part.begin; k + 1 < part.end; ++k) {
            out.push_back({d.pts[k], d.pts[k + 1]});
        }
    }
    return out;
}

/// Nearest-segment queries against one side: brute force when small, an STR tree when large.
class Target {
public:
    explicit Target(std::vector<Seg> segs) : m_segs(std::move(segs))
    {
        for (const Seg& s : m_segs) {
            m_sorted.push_back(normalised(s));
        }
        std::sort(m_sorted.begin(), m_sorted.end());
        if (m_segs.size() <= 32) {
            return;
        }
        std::vector<Box> boxes;
        for (const Seg& s : m_segs) {
            boxes.push_back(segment_box(s.a, s.b));
        }
        m_tree.build(std::move(boxes));
    }
    std::pair<std::uint32_t, double> nearest(Pt p) const
    {
        if (m_tree.size() == 0) {
            std::pair<std::uint32_t, double> best{0, k_inf};
            for (std::uint32_t i = 0; i < m_segs.size(); ++i) {
                const double d = point_segment_distance(p, m_segs[i].a, m_segs[i].b);
                if (d < best.second) {
                    best = {i, d};
                }
            }
            return best;
        }
        return m_tree.nearest(p, [&](std::uint32_t i) { return point_segment_distance(p, m_segs[i].a, m_segs[i].b); });
    }
    double distance_to(std::uint32_t i, Pt p) const { return point_segment_distance(p, m_segs[i].a, m_segs[i].b); }
    Pt closest(std::uint32_t i, Pt p) const
    {
        Pt c;
        point_segment_distance(p, m_segs[i].a, m_segs[i].b, &c);
        return c;
    }
    const std::vector<Seg>& segments() const { return m_segs; }
    /// True when this side has exactly this segment (either direction): every point of it is at 0.
    bool has(const Seg& s) const { return std::binary_search(m_sorted.begin(), m_sorted.end(), normalised(s)); }

private:
    using Key = std::array<double, 4>;
    static Key normalised(const Seg& s)
    {
        return s.b < s.a ? Key{s.b.x, s.b.y, s.a.x, s.a.y} : Key{s.a.x, s.a.y, s.b.x, s.b.y};
    }
    std::vector<Seg> m_segs;
    std::vector<Key> m_sorted;
    StrTree m_tree;
};

/// max over t in [0,1] of min(l1(t), l2(t)) for lines l1: a0 -> a1 and l2: b0 -> b1.
double max_of_min_chords(double a0, double a1, double b0, double b1)
{
    double best = std::max(std::min(a0, b0), std::min(a1, b1));
    const double d0 = a0 - b0, d1 = a1 - b1;
    if ((d0 < 0 && d1 > 0) || (d0 > 0 && d1 < 0)) {
        const double t = d0 / (d0 - d1);
        best = std::max(best, a0 + t * (a1 - a0));
    }
    return best;
}

struct Far {
    double distance = 0;
    Pt where; // the farthest point
    Pt near;  // its nearest point on the other side
};

struct Interval {
    double t0, t1, f0, f1;
    std::uint32_t n0, n1;
};

void directed_edge(const Seg& s, const Target& to, double eps, Far& far)
{
    const auto at = [&](double t) { return Pt{s.a.x + t * (s.b.x - s.a.x), s.a.y + t * (s.b.y - s.a.y)}; };
    const auto note = [&](double f, double t, std::uint32_t nearest) {
        if (f > far.distance) {
            far = {f, at(t), to.closest(nearest, at(t))};
        }
    };
    const double length = distance(s.a, s.b);
    const auto [n0, f0] = to.nearest(s.a);
    const auto [n1, f1] = to.nearest(s.b);
    note(f0, 0, n0);
    note(f1, 1, n1);
    std::vector<Interval> stack{{0, 1, f0, f1, n0, n1}};
    while (!stack.empty()) {
        const Interval iv = stack.back();
        stack.pop_back();
        const double len = length * (iv.t1 - iv.t0);
        double bound = 0.5 * (iv.f0 + iv.f1 + len);
        if (iv.n0 == iv.n1) {
            bound = std::min(bound, std::max(iv.f0, iv.f1));
        } else {
            const double g0 = to.distance_to(iv.n0, at(iv.t1)), g1 = to.distance_to(iv.n1, at(iv.t0));
            bound = std::min(bound, max_of_min_chords(iv.f0, g0, g1, iv.f1));
        }
        if (bound <= far.distance + eps || len <= eps) {
            continue;
        }
        const double tm = 0.5 * (iv.t0 + iv.t1);
        const auto [nm, fm] = to.nearest(at(tm));
        note(fm, tm, nm);
        stack.push_back({iv.t0, tm, iv.f0, fm, iv.n0, nm});
        stack.push_back({tm, iv.t1, fm, iv.f1, nm, iv.n1});
    }
}

/// Edges in fixed chunks (simple_partitioner splits the same way whatever the thread count), each
/// chunk pruning with its own best, merged in chunk order: the result does not depend on threads.
Far directed(const Target& from, const Target& to, double eps)
{
    const std::vector<Seg>& segs = from.segments();
    constexpr std::size_t chunk = 256;
    std::vector<Far> per_chunk((segs.size() + chunk - 1) / chunk);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, per_chunk.size(), 1),
        [&](const auto& range) {
            for (std::size_t c = range.begin(); c < range.end(); ++c) {
                for (std::size_t i = c * chunk; i < std::min(segs.size(), (c + 1) * chunk); ++i) {
                    if (!to.has(segs[i])) {
                        directed_edge(segs[i], to, eps, per_chunk[c]);
                    }
                }
            }
        },
        tbb::simple_partitioner());
    Far far;
    for (const Far& f : per_chunk) {
        if (f.distance > far.distance) {
            far = f;
        }
    }
    return far;
}

} // namespace

namespace {

/// Input indexes with a non-empty match.
std::vector<std::uint32_t> measurable_pairs(const Context& c)
{
    std::vector<std::uint32_t> pairs;
    const auto measurable = [](const Feature& f) { return f.kind == FeatureKind::line || f.kind == FeatureKind::polygon; };
    for (std::uint32_t i = 0; i < c.a.features.size(); ++i) {
        if (c.match[i] >= 0 && measurable(c.a.features[i]) && measurable(c.b.features[static_cast<std::size_t>(c.match[i])])) {
            pairs.push_back(i);
        }
    }
    return pairs;
}

AssessExample feature_hausdorff(const Context& c, std::uint32_t i)
{
    const Feature& fa = c.a.features[i];
    const Feature& fb = c.b.features[static_cast<std::size_t>(c.match[i])];
    const Target ta(segments_of(c.a, fa));
    const Target tb(segments_of(c.b, fb));
    const double eps = c.tolerance * 1e-3;
    Far far = directed(ta, tb, eps);
    const Far back = directed(tb, ta, eps);
    if (back.distance > far.distance) {
        far = back;
    }
    return pair_example(fa.fid, fb.fid, far.where, far.near, far.distance);
}

void summarise(std::vector<AssessExample>& per_pair, AssessReport& r)
{
    std::vector<double> values;
    for (const AssessExample& e : per_pair) {
        values.push_back(e.value);
    }
    std::sort(values.begin(), values.end());
    if (!values.empty()) {
        r.max_hausdorff = values.back();
        // Nearest-rank 99th percentile.
        const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(values.size())));
        r.p99_hausdorff = values[std::max<std::size_t>(rank, 1) - 1];
    }
}

} // namespace

void measure_hausdorff(const Context& c, AssessReport& r)
{
    const std::vector<std::uint32_t> pairs = measurable_pairs(c);
    std::vector<AssessExample> per_pair(pairs.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 1), [&](const auto& range) {
        for (std::size_t p = range.begin(); p < range.end(); ++p) {
            per_pair[p] = feature_hausdorff(c, pairs[p]);
        }
    });
    summarise(per_pair, r);
    for (AssessExample& e : per_pair) {
        if (e.value <= 2 * c.tolerance) {
            continue;
        }
        ++r.n_drift;
        e.excused_by = c.excuses.explain(Defect::drift, e.fid_a);
        if (!e.excused_by.empty()) {
            ++r.excused_counts.drift;
            note_excused(r, e, "drift");
        }
    }
    keep_first(per_pair, c.k, by_value_desc);
    r.largest_hausdorff = std::move(per_pair);
}

} // namespace trisnap::assess
