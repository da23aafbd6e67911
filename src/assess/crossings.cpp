// Crossings of the output (pairs of distinct segments meeting other than at a common endpoint),
// and which are new: a crossing is known when, for some owner of each segment, their input
// features crossed each other (or the one input feature crossed itself) in the input. The
// input is searched only among the inputs of crossing outputs (nothing when none cross).
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

/// The pairs of input features that cross in the input, among the features `keep` marks.
FeaturePairs input_crossings(const LayerData& a, const std::vector<std::uint8_t>& keep)
{
    const DistinctSegments d = distinct_segments(a, &keep);
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

struct Crossing {
    std::uint32_t i, j; // distinct segments, i < j
    Pt where;
};

std::vector<Crossing> output_crossings(const DistinctSegments& out)
{
    tbb::combinable<std::vector<Crossing>> found;
    for_each_crossing(out, [&](std::uint32_t i, std::uint32_t j, Pt where) { found.local().push_back({i, j, where}); });
    std::vector<Crossing> all;
    found.combine_each([&](const std::vector<Crossing>& v) { all.insert(all.end(), v.begin(), v.end()); });
    return all;
}

/// The inputs of every feature owning a segment of a crossing: only they can have crossed before.
std::vector<std::uint8_t> inputs_of_crossings(const Context& c, const DistinctSegments& out, const std::vector<Crossing>& found)
{
    std::vector<std::uint8_t> keep(c.a.features.size(), 0);
    const auto mark = [&](const Segment& s) {
        for (std::uint32_t u = s.owners_begin; u < s.owners_end; ++u) {
            const std::int64_t i = c.input_of[out.owners[u]];
            if (i >= 0) {
                keep[static_cast<std::size_t>(i)] = 1;
            }
        }
    };
    for (const Crossing& x : found) {
        mark(out.segments[x.i]);
        mark(out.segments[x.j]);
    }
    return keep;
}

} // namespace

void measure_crossings(const Context& c, const DistinctSegments& out, AssessReport& r)
{
    const std::vector<Crossing> found = output_crossings(out);
    const FeaturePairs input = found.empty() ? FeaturePairs{} : input_crossings(c.a, inputs_of_crossings(c, out, found));
    std::vector<AssessExample> examples;
    for (const Crossing& x : found) {
        const Segment& s = out.segments[x.i];
        const Segment& t = out.segments[x.j];
        const bool known = crossed_in_input(c, input, out, s, t);
        r.n_crossings_new += known ? 0 : 1;
        const std::int64_t fa = c.b.features[s.feature].fid;
        const std::int64_t fb = c.b.features[t.feature].fid;
        AssessExample e = example_at(std::min(fa, fb), std::max(fa, fb), x.where);
        e.is_new = !known;
        push_bounded(examples, std::move(e), c.k, new_first);
    }
    r.n_crossings = static_cast<std::int64_t>(found.size());
    keep_first(examples, c.k, new_first);
    r.crossings = std::move(examples);
}

} // namespace trisnap::assess
