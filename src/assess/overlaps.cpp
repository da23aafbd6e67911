// Overlapping output polygons in time that grows with the pairs of *distinct* geometries:
// features with identical geometry (stacked copies: 10,000 copies of one square make 5·10^7
// overlapping pairs) form one group, measured once; a pair of groups stands for every pair of
// their members. Which pairs are new is counted from the other side: the input pairs that
// overlap (candidate pairs among the inputs of overlapping outputs only, so a clean coverage
// costs nothing here) whose outputs overlap too are the known ones; the rest are new.
#include "assess/measures.hpp"
#include "assess/overlap_test.hpp"
#include "assess/polygon_pairs.hpp"

#include <tbb/combinable.h>

#include <algorithm>
#include <tuple>
#include <utility>

namespace trisnap::assess {
namespace {

using FeaturePairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>; // lo < hi, sorted
constexpr std::uint32_t k_none = UINT32_MAX;

/// Output polygons grouped by identical geometry (same parts, same points in the same order).
struct Groups {
    std::vector<std::uint32_t> group_of;             // per feature; k_none for non-polygons
    std::vector<std::vector<std::uint32_t>> members; // per group, feature indexes in FID order
    std::vector<std::uint32_t> reps;                 // per group, its first member
};

/// A total order on geometries (box first: cheap and nearly always decisive), ties by FID.
bool geometry_less(const LayerData& d, std::uint32_t x, std::uint32_t y)
{
    const Feature& fx = d.features[x];
    const Feature& fy = d.features[y];
    const auto box_x = std::tie(fx.box.xmin, fx.box.ymin, fx.box.xmax, fx.box.ymax);
    const auto box_y = std::tie(fy.box.xmin, fy.box.ymin, fy.box.xmax, fy.box.ymax);
    if (box_x != box_y) {
        return box_x < box_y;
    }
    const auto px = d.pts.begin() + d.parts[fx.part_begin].begin;
    const auto py = d.pts.begin() + d.parts[fy.part_begin].begin;
    const auto ex = d.pts.begin() + d.parts[fx.part_end - 1].end;
    const auto ey = d.pts.begin() + d.parts[fy.part_end - 1].end;
    if (std::lexicographical_compare(px, ex, py, ey)) {
        return true;
    }
    if (std::lexicographical_compare(py, ey, px, ex)) {
        return false;
    }
    return fx.fid < fy.fid;
}

bool same_geometry(const LayerData& d, std::uint32_t x, std::uint32_t y)
{
    const Feature& fx = d.features[x];
    const Feature& fy = d.features[y];
    if (fx.part_end - fx.part_begin != fy.part_end - fy.part_begin) {
        return false;
    }
    for (std::uint32_t i = 0; i < fx.part_end - fx.part_begin; ++i) {
        const Part& a = d.parts[fx.part_begin + i];
        const Part& b = d.parts[fy.part_begin + i];
        if (a.type != b.type || a.end - a.begin != b.end - b.begin ||
            !std::equal(d.pts.begin() + a.begin, d.pts.begin() + a.end, d.pts.begin() + b.begin)) {
            return false;
        }
    }
    return true;
}

Groups group_identical(const LayerData& d)
{
    std::vector<std::uint32_t> order;
    for (std::uint32_t i = 0; i < d.features.size(); ++i) {
        if (d.features[i].kind == FeatureKind::polygon) {
            order.push_back(i);
        }
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return geometry_less(d, x, y); });
    Groups g;
    g.group_of.assign(d.features.size(), k_none);
    for (std::size_t k = 0; k < order.size(); ++k) {
        if (k == 0 || !same_geometry(d, order[k - 1], order[k])) {
            g.members.emplace_back();
            g.reps.push_back(order[k]);
        }
        g.members.back().push_back(order[k]);
        g.group_of[order[k]] = static_cast<std::uint32_t>(g.members.size() - 1);
    }
    return g;
}

/// Members of group g overlap members of group h (g <= h; g == h: with each other).
struct Relation {
    std::uint32_t g, h;
    double area; // of one pair
    Pt where;    // centroid of the intersection
};

bool relation_less(const Relation& x, const Relation& y) { return std::tie(x.g, x.h) < std::tie(y.g, y.h); }

std::vector<Relation> group_overlaps(const LayerData& d, const Groups& groups, const std::vector<std::int8_t>& interior_left,
                                     const std::vector<std::uint8_t>& invalid)
{
    tbb::combinable<std::vector<Relation>> found;
    const auto test = [&](std::uint32_t i, std::uint32_t j) {
        Pt where;
        const double area = overlap_area(d, interior_left, invalid, i, j, &where);
        if (area > 0) {
            const std::uint32_t g = groups.group_of[i];
            const std::uint32_t h = groups.group_of[j];
            found.local().push_back({std::min(g, h), std::max(g, h), area, where});
        }
    };
    for_candidate_pairs(index_polygons(d, groups.reps), true, test);
    for (std::uint32_t g = 0; g < groups.members.size(); ++g) {
        if (groups.members[g].size() > 1) {
            test(groups.reps[g], groups.reps[g]);
        }
    }
    std::vector<Relation> all;
    found.combine_each([&](const auto& v) { all.insert(all.end(), v.begin(), v.end()); });
    std::sort(all.begin(), all.end(), relation_less);
    return all;
}

std::int64_t pair_count(const Groups& groups, const Relation& rel)
{
    const auto m = static_cast<std::int64_t>(groups.members[rel.g].size());
    const auto n = static_cast<std::int64_t>(groups.members[rel.h].size());
    return rel.g == rel.h ? m * (m - 1) / 2 : m * n;
}

std::pair<std::uint32_t, std::uint32_t> ordered(std::uint32_t u, std::uint32_t v) { return {std::min(u, v), std::max(u, v)}; }

/// The input features whose outputs overlap something: only their pairs can be known overlaps.
std::vector<std::uint32_t> inputs_of_overlaps(const Context& c, const Groups& groups, const std::vector<Relation>& rels)
{
    std::vector<std::uint8_t> involved(groups.members.size(), 0);
    for (const Relation& rel : rels) {
        involved[rel.g] = 1;
        involved[rel.h] = 1;
    }
    std::vector<std::uint32_t> inputs;
    for (std::uint32_t i = 0; i < c.match.size(); ++i) {
        const std::int64_t o = c.match[i];
        const std::uint32_t g = o < 0 ? k_none : groups.group_of[static_cast<std::size_t>(o)];
        if (g != k_none && involved[g]) {
            inputs.push_back(i);
        }
    }
    return inputs;
}

/// Pairs of the input polygon features `candidates` whose interiors meet.
FeaturePairs input_overlaps(const LayerData& a, const std::vector<std::uint32_t>& candidates)
{
    if (candidates.empty()) {
        return {};
    }
    const std::vector<std::uint8_t> invalid = invalid_polygons(a, &candidates, nullptr, 0);
    const std::vector<std::int8_t> interior_left = interior_left_of_parts(a);
    tbb::combinable<FeaturePairs> found;
    for_candidate_pairs(index_polygons(a, candidates), true, [&](std::uint32_t i, std::uint32_t j) {
        if (interiors_overlap(a, interior_left, invalid, i, j)) {
            found.local().push_back(ordered(i, j));
        }
    });
    FeaturePairs all;
    found.combine_each([&](const FeaturePairs& v) { all.insert(all.end(), v.begin(), v.end()); });
    std::sort(all.begin(), all.end());
    return all;
}

/// How many overlapping output pairs have inputs that overlapped too.
std::int64_t known_overlaps(const Context& c, const Groups& groups, const std::vector<Relation>& rels,
                            const FeaturePairs& input)
{
    std::int64_t known = 0;
    for (const auto& [p, q] : input) {
        const std::int64_t op = c.match[p];
        const std::int64_t oq = c.match[q];
        if (op < 0 || oq < 0) {
            continue;
        }
        const std::uint32_t g = groups.group_of[static_cast<std::size_t>(op)];
        const std::uint32_t h = groups.group_of[static_cast<std::size_t>(oq)];
        if (g == k_none || h == k_none) {
            continue;
        }
        const Relation key{std::min(g, h), std::max(g, h), 0, {}};
        known += std::binary_search(rels.begin(), rels.end(), key, relation_less) ? 1 : 0;
    }
    return known;
}

/// The example pairs of one relation that can be among the k smallest by FIDs: the first k
/// members of each group suffice (any other pair has k smaller pairs before it).
void relation_examples(const Context& c, const Groups& groups, const Relation& rel, const FeaturePairs& input,
                       std::vector<AssessExample>& out)
{
    const std::vector<std::uint32_t>& mg = groups.members[rel.g];
    const std::vector<std::uint32_t>& mh = groups.members[rel.h];
    for (std::size_t x = 0; x < std::min(mg.size(), c.k); ++x) {
        for (std::size_t y = rel.g == rel.h ? x + 1 : 0; y < std::min(mh.size(), c.k + (rel.g == rel.h ? 1 : 0)); ++y) {
            const std::int64_t ia = c.input_of[mg[x]];
            const std::int64_t ib = c.input_of[mh[y]];
            const bool known = ia >= 0 && ib >= 0 &&
                               std::binary_search(input.begin(), input.end(),
                                                  ordered(static_cast<std::uint32_t>(ia), static_cast<std::uint32_t>(ib)));
            const std::int64_t fa = c.b.features[mg[x]].fid;
            const std::int64_t fb = c.b.features[mh[y]].fid;
            AssessExample e = example_at(std::min(fa, fb), std::max(fa, fb), rel.where, rel.area);
            e.is_new = !known;
            out.push_back(std::move(e));
        }
    }
}

} // namespace

void measure_overlaps(const Context& c, const std::vector<std::uint8_t>& invalid, AssessReport& r)
{
    const Groups groups = group_identical(c.b);
    const std::vector<Relation> rels = group_overlaps(c.b, groups, interior_left_of_parts(c.b), invalid);
    const FeaturePairs input = input_overlaps(c.a, inputs_of_overlaps(c, groups, rels));
    std::vector<AssessExample> examples;
    for (const Relation& rel : rels) {
        const std::int64_t n = pair_count(groups, rel);
        r.n_overlaps += n;
        r.overlap_area += static_cast<double>(n) * rel.area;
        relation_examples(c, groups, rel, input, examples);
    }
    r.n_overlaps_new = r.n_overlaps - known_overlaps(c, groups, rels, input);
    keep_first(examples, c.k, new_first);
    r.overlaps = std::move(examples);
}

} // namespace trisnap::assess
