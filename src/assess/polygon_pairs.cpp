// Pairs of polygon features: overlaps among the outputs and boundaries lost between neighbours.
// Candidate pairs come from an STR tree over feature boxes; each pair then looks only at the
// segments inside the intersection of the two boxes (a shared boundary or a crossing lies there).
#include "assess/measures.hpp"
#include "assess/overlap_test.hpp"
#include "assess/str_tree.hpp"

#include <ogr_api.h>
#include <ogr_geometry.h>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <functional>
#include <memory>

namespace trisnap::assess {
namespace {

struct Seg {
    Pt a, b;
};

std::vector<Seg> window_segments(const LayerData& d, const Feature& f, const Box& window)
{
    std::vector<Seg> out;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i)
        for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k)
            if (d.pts[k] != d.pts[k + 1] && segment_box(d.pts[k], d.pts[k + 1]).intersects(window))
                out.push_back({d.pts[k], d.pts[k + 1]});
    return out;
}

/// Calls fn(a, b) for pairs whose boxes meet until it returns true; true when it did.
bool any_near_pair(const std::vector<Seg>& sa, const std::vector<Seg>& sb, const std::function<bool(const Seg&, const Seg&)>& fn)
{
    if (sa.size() * sb.size() <= 1024) {
        for (const Seg& x : sa)
            for (const Seg& y : sb)
                if (fn(x, y)) return true;
        return false;
    }
    std::vector<Box> boxes;
    boxes.reserve(sb.size());
    for (const Seg& y : sb) boxes.push_back(segment_box(y.a, y.b));
    const StrTree tree(std::move(boxes));
    bool stop = false;
    for (const Seg& x : sa) {
        tree.query(segment_box(x.a, x.b), [&](std::uint32_t j) { stop = stop || fn(x, sb[j]); });
        if (stop) return true;
    }
    return false;
}

/// Length of boundary the two features share (exactly collinear overlaps), and where the
/// longest shared piece is.
double shared_length(const LayerData& d, const Feature& fa, const Feature& fb, Pt* where)
{
    const Box window = fa.box.intersection(fb.box);
    const auto sa = window_segments(d, fa, window), sb = window_segments(d, fb, window);
    double total = 0, longest = 0;
    any_near_pair(sa, sb, [&](const Seg& x, const Seg& y) {
        const double len = collinear_overlap(x.a, x.b, y.a, y.b);
        total += len;
        if (len > longest) {
            longest = len;
            const Pt lo = std::max(std::min(x.a, x.b), std::min(y.a, y.b));
            const Pt hi = std::min(std::max(x.a, x.b), std::max(y.a, y.b));
            *where = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)};
        }
        return false;
    });
    return total;
}

/// Area of the polygonal parts of a geometry (an intersection may hold lines and points too).
double surface_area(const OGRGeometry& g)
{
    const OGRwkbGeometryType type = wkbFlatten(g.getGeometryType());
    if (OGR_GT_IsSurface(type)) return g.toSurface()->get_Area();
    if (!OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) return 0;
    double area = 0;
    for (const OGRGeometry* member : *g.toGeometryCollection()) area += surface_area(*member);
    return area;
}

/// Area of the intersection of two polygon features through OGR (GEOS), and its centroid.
double intersection_area(const LayerData& d, const Feature& fa, const Feature& fb, Pt* where)
{
    std::unique_ptr<OGRGeometry> ga(d.make_ogr_polygon(fa)), gb(d.make_ogr_polygon(fb));
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::unique_ptr<OGRGeometry> inter(ga->Intersection(gb.get()));
    if (!inter) { // invalid operands (counted as invalid already): measure their repaired forms
        std::unique_ptr<OGRGeometry> va(ga->MakeValid()), vb(gb->MakeValid());
        if (va && vb) inter.reset(va->Intersection(vb.get()));
    }
    CPLPopErrorHandler();
    if (!inter || inter->IsEmpty()) return 0;
    const double area = surface_area(*inter);
    OGRPoint centroid;
    if (area > 0 && inter->Centroid(&centroid) == OGRERR_NONE) *where = {centroid.getX(), centroid.getY()};
    return area;
}

/// The exact boundary test first (valid polygons only), GEOS's overlay for the area or when it
/// cannot decide.
double overlap_of(const LayerData& d, const std::vector<std::int8_t>& interior_left, const std::vector<std::uint8_t>& invalid,
                  std::uint32_t i, std::uint32_t j, Pt* where)
{
    const Feature& fa = d.features[i];
    const Feature& fb = d.features[j];
    if (!invalid[i] && !invalid[j] && interiors_meet(d, interior_left, fa, fb) == OverlapVerdict::disjoint) return 0;
    return intersection_area(d, fa, fb, where);
}

struct PolygonIndex {
    std::vector<std::uint32_t> ids; // polygon features
    StrTree tree;                   // over their boxes, item k = ids[k]
};

PolygonIndex index_polygons(const LayerData& d)
{
    PolygonIndex index;
    std::vector<Box> boxes;
    for (std::uint32_t i = 0; i < d.features.size(); ++i)
        if (d.features[i].kind == FeatureKind::polygon) index.ids.push_back(i), boxes.push_back(d.features[i].box);
    index.tree.build(std::move(boxes));
    return index;
}

/// Calls fn(i, j) for polygon pairs i < j (feature indexes) whose boxes meet, in parallel.
template <class Fn>
void for_candidate_pairs(const LayerData& d, const PolygonIndex& index, bool positive_area, Fn&& fn)
{
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, index.ids.size(), 16), [&](const auto& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const Box& box = index.tree.box(static_cast<std::uint32_t>(k));
            index.tree.query(box, [&](std::uint32_t m) {
                if (m <= k || (positive_area && !box.overlaps(index.tree.box(m)))) return;
                fn(index.ids[k], index.ids[m]);
            });
        }
    });
    (void)d;
}

} // namespace

/// True when the inputs of two output features overlapped already (unmatched: they did not).
bool overlapped_in_input(const LayerData& a, const std::vector<std::int64_t>& input_of, std::uint32_t i, std::uint32_t j)
{
    if (input_of[i] < 0 || input_of[j] < 0) return false;
    const Feature& fa = a.features[static_cast<std::size_t>(input_of[i])];
    const Feature& fb = a.features[static_cast<std::size_t>(input_of[j])];
    if (fa.kind != FeatureKind::polygon || fb.kind != FeatureKind::polygon || !fa.box.overlaps(fb.box)) return false;
    Pt unused;
    return intersection_area(a, fa, fb, &unused) > 0;
}

void measure_overlaps(const LayerData& a, const LayerData& b, const Matching& match, const std::vector<std::uint8_t>& invalid,
                      AssessReport& r, std::size_t k)
{
    const PolygonIndex index = index_polygons(b);
    const std::vector<std::int8_t> interior_left = interior_left_of_parts(b);
    std::vector<std::int64_t> input_of(b.features.size(), -1);
    for (std::size_t i = 0; i < match.size(); ++i)
        if (match[i] >= 0) input_of[static_cast<std::size_t>(match[i])] = static_cast<std::int64_t>(i);
    tbb::combinable<std::vector<AssessExample>> found;
    for_candidate_pairs(b, index, true, [&](std::uint32_t i, std::uint32_t j) {
        Pt where;
        const double area = overlap_of(b, interior_left, invalid, i, j, &where);
        if (area <= 0) return;
        const std::int64_t fa = std::min(b.features[i].fid, b.features[j].fid);
        const std::int64_t fb = std::max(b.features[i].fid, b.features[j].fid);
        const bool known = overlapped_in_input(a, input_of, i, j); // few pairs: GEOS is fine here
        found.local().push_back({fa, fb, where.x, where.y, 0, 0, area, known ? "in input" : "new", {}});
    });
    std::vector<AssessExample> all;
    found.combine_each([&](const auto& v) { all.insert(all.end(), v.begin(), v.end()); });
    std::sort(all.begin(), all.end(), by_fids); // a fixed order makes the float sum repeatable
    for (const AssessExample& e : all) {
        r.overlap_area += e.value;
        r.n_overlaps_new += e.text == "new";
    }
    r.n_overlaps = static_cast<std::int64_t>(all.size());
    keep_first(all, k, by_fids);
    r.overlaps = std::move(all);
}

void measure_gaps(const LayerData& a, const LayerData& b, const Matching& match, double tolerance, AssessReport& r,
                  std::size_t k)
{
    const PolygonIndex index = index_polygons(a);
    tbb::combinable<std::vector<AssessExample>> found;
    tbb::combinable<std::int64_t> shared;
    for_candidate_pairs(a, index, false, [&](std::uint32_t i, std::uint32_t j) {
        Pt where;
        const double length = shared_length(a, a.features[i], a.features[j], &where);
        if (length <= 2 * tolerance) return;
        ++shared.local();
        if (match[i] < 0 || match[j] < 0) return; // a lost feature is counted as missing
        const Feature& oi = b.features[static_cast<std::size_t>(match[i])];
        const Feature& oj = b.features[static_cast<std::size_t>(match[j])];
        if (oi.kind != FeatureKind::polygon || oj.kind != FeatureKind::polygon) return;
        Pt unused;
        if (oi.box.intersects(oj.box) && shared_length(b, oi, oj, &unused) > 0) return;
        std::int64_t fa = a.features[i].fid, fb = a.features[j].fid;
        if (fb < fa) std::swap(fa, fb);
        found.local().push_back({fa, fb, where.x, where.y, 0, 0, length, "", {}});
    });
    r.n_shared_in = shared.combine(std::plus<>());
    std::vector<AssessExample> all;
    found.combine_each([&](const auto& v) { all.insert(all.end(), v.begin(), v.end()); });
    r.gaps_new = static_cast<std::int64_t>(all.size());
    keep_first(all, k, by_fids);
    r.gaps_new_examples = std::move(all);
}

} // namespace trisnap::assess
