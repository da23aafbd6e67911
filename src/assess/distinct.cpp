#include "assess/distinct.hpp"

#include <algorithm>

namespace trisnap::assess {
namespace {

bool segment_less(const Segment& x, const Segment& y)
{
    if (x.a != y.a) {
        return x.a < y.a;
    }
    if (x.b != y.b) {
        return x.b < y.b;
    }
    return x.feature < y.feature;
}

std::vector<Segment> all_segments(const LayerData& d, const std::vector<std::uint8_t>* keep)
{
    std::vector<Segment> s;
    s.reserve(keep ? 0 : d.pts.size());
    for (std::uint32_t f = 0; f < d.features.size(); ++f) {
        if (keep && !(*keep)[f]) {
            continue;
        }
        for (std::uint32_t i = d.features[f].part_begin; i < d.features[f].part_end; ++i) {
            for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k) {
                const Pt p = d.pts[k];
                const Pt q = d.pts[k + 1];
                if (p != q) {
                    s.push_back({std::min(p, q), std::max(p, q), f, 0, 0});
                }
            }
        }
    }
    std::sort(s.begin(), s.end(), segment_less);
    return s;
}

} // namespace

std::vector<Owned> distinct_vertices(const LayerData& d)
{
    std::vector<Owned> v;
    v.reserve(d.pts.size());
    for (std::uint32_t f = 0; f < d.features.size(); ++f) {
        for (std::uint32_t i = d.features[f].part_begin; i < d.features[f].part_end; ++i) {
            for (std::uint32_t k = d.parts[i].begin; k < d.parts[i].end; ++k) {
                v.push_back({d.pts[k], f});
            }
        }
    }
    std::sort(v.begin(), v.end(), [](const Owned& x, const Owned& y) {
        return x.p < y.p || (x.p == y.p && x.feature < y.feature);
    });
    v.erase(std::unique(v.begin(), v.end(), [](const Owned& x, const Owned& y) { return x.p == y.p; }), v.end());
    return v;
}

DistinctSegments distinct_segments(const LayerData& d, const std::vector<std::uint8_t>* keep)
{
    const std::vector<Segment> all = all_segments(d, keep);
    DistinctSegments out;
    out.owners.reserve(all.size());
    for (const Segment& s : all) {
        const bool repeat = !out.segments.empty() && out.segments.back().a == s.a && out.segments.back().b == s.b;
        if (!repeat) {
            out.segments.push_back(s);
            out.segments.back().owners_begin = static_cast<std::uint32_t>(out.owners.size());
        }
        if (out.owners.size() == out.segments.back().owners_begin || out.owners.back() != s.feature) {
            out.owners.push_back(s.feature);
        }
        out.segments.back().owners_end = static_cast<std::uint32_t>(out.owners.size());
    }
    std::vector<Box> boxes(out.segments.size());
    for (std::size_t i = 0; i < out.segments.size(); ++i) {
        boxes[i] = segment_box(out.segments[i].a, out.segments[i].b);
    }
    out.tree.build(std::move(boxes));
    return out;
}

std::vector<AssessExample> gather(Examples& per_thread)
{
    std::vector<AssessExample> all;
    per_thread.combine_each([&](const std::vector<AssessExample>& v) { all.insert(all.end(), v.begin(), v.end()); });
    return all;
}

} // namespace trisnap::assess
