// Crossings of the output (pairs of distinct segments meeting other than at a common endpoint),
// and which are new: a crossing is known when, for some owner of each segment, their input
// features crossed each other (or the one input feature crossed itself) in the input.
#include "assess/distinct.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <functional>
#include <utility>

namespace trisnap::assess {
namespace {

using FeaturePairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>; // lo <= hi, sorted

/// Calls fn(i, j, where) for every crossing pair of distinct segments i < j, in parallel.
template <class Fn>
void for_each_crossing(const DistinctSegments& d, Fn&& fn)
{
    const std::vector<Segment>& s = d.segments;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.size(), 1024), [&](const auto& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            d.tree.query(d.tree.box(static_cast<std::uint32_t>(i)), [&](std::uint32_t j) {
                Pt where;
                if (j > i && segment_contact(s[i].a, s[i].b, s[j].a, s[j].b, &where) == SegmentContact::crossing) {
                    fn(static_cast<std::uint32_t>(i), j, where);
                }
            });
        }
    });
}

std::pair<std::uint32_t, std::uint32_t> ordered(std::uint32_t u, std::uint32_t v) { return {std::min(u, v), std::max(u, v)}; }

/// The pairs of input features that cross in the input.
FeaturePairs input_crossings(const LayerData& a)
{
    const DistinctSegments d = distinct_segments(a);
    tbb::combinable<FeaturePairs> found;
    for_each_crossing(d, [&](std::uint32_t i, std::uint32_t j, Pt) {
        FeaturePairs& mine = found.local();
        for (std::uint32_t u = d.segments[i].owners_begin; u < d.segments[i].owners_end; ++u) {
            for (std::uint32_t v = d.segments[j].owners_begin; v < d.segments[j].owners_end; ++v) {
                mine.push_back(ordered(d.owners[u], d.owners[v]));
            }
        }
    });
    FeaturePairs all;
    found.combine_each([&](const FeaturePairs& v) { all.insert(all.end(), v.begin(), v.end()); });
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
}

bool crossed_in_input(const Context& c, const FeaturePairs& input, const DistinctSegments& d, const Segment& x,
                      const Segment& y)
{
    for (std::uint32_t u = x.owners_begin; u < x.owners_end; ++u) {
        for (std::uint32_t v = y.owners_begin; v < y.owners_end; ++v) {
            const std::int64_t iu = c.input_of[d.owners[u]];
            const std::int64_t iv = c.input_of[d.owners[v]];
            if (iu >= 0 && iv >= 0 &&
                std::binary_search(input.begin(), input.end(),
                                   ordered(static_cast<std::uint32_t>(iu), static_cast<std::uint32_t>(iv)))) {
                return true;
            }
        }
    }
    return false;
}

} // namespace

void measure_crossings(const Context& c, const DistinctSegments& out, AssessReport& r)
{
    const FeaturePairs input = input_crossings(c.a);
    tbb::combinable<std::int64_t> count;
    tbb::combinable<std::int64_t> fresh;
    Examples found;
    for_each_crossing(out, [&](std::uint32_t i, std::uint32_t j, Pt where) {
        const Segment& x = out.segments[i];
        const Segment& y = out.segments[j];
        const bool known = crossed_in_input(c, input, out, x, y);
        ++count.local();
        fresh.local() += known ? 0 : 1;
        std::int64_t fa = c.b.features[x.feature].fid;
        std::int64_t fb = c.b.features[y.feature].fid;
        if (fb < fa) {
            std::swap(fa, fb);
        }
        AssessExample e = example_at(fa, fb, where);
        e.is_new = !known;
        push_bounded(found.local(), std::move(e), c.k, new_first);
    });
    r.n_crossings = count.combine(std::plus<>());
    r.n_crossings_new = fresh.combine(std::plus<>());
    std::vector<AssessExample> all = gather(found);
    keep_first(all, c.k, new_first);
    r.crossings = std::move(all);
}

} // namespace trisnap::assess
