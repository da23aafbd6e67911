// Pairs of polygon features: the helpers overlaps and gaps share, and boundaries lost between
// neighbours. Candidate pairs come from an STR tree over feature boxes; each pair then looks
// only at the segments inside the intersection of the two boxes (a shared boundary or a
// crossing lies there).
#include "assess/polygon_pairs.hpp"

#include "assess/measures.hpp"
#include "assess/overlap_test.hpp"

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
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k) {
            if (d.pts[k] != d.pts[k + 1] && segment_box(d.pts[k], d.pts[k + 1]).intersects(window)) {
                out.push_back({d.pts[k], d.pts[k + 1]});
            }
        }
    }
    return out;
}

/// Calls fn(a, b) for pairs whose boxes meet until it returns true; true when it did.
bool any_near_pair(const std::vector<Seg>& sa, const std::vector<Seg>& sb, const std::function<bool(const Seg&, const Seg&)>& fn)
{
    if (sa.size() * sb.size() <= 1024) {
        for (const Seg& x : sa) {
            for (const Seg& y : sb) {
                if (fn(x, y)) {
                    return true;
                }
            }
        }
        return false;
    }
    std::vector<Box> boxes;
    boxes.reserve(sb.size());
    for (const Seg& y : sb) {
        boxes.push_back(segment_box(y.a, y.b));
    }
    const StrTree tree(std::move(boxes));
    bool stop = false;
    for (const Seg& x : sa) {
        tree.query(segment_box(x.a, x.b), [&](std::uint32_t j) { stop = stop || fn(x, sb[j]); });
        if (stop) {
            return true;
        }
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
    if (OGR_GT_IsSurface(type)) {
        return g.toSurface()->get_Area();
    }
    if (!OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
        return 0;
    }
    double area = 0;
    for (const OGRGeometry* member : *g.toGeometryCollection()) {
        area += surface_area(*member);
    }
    return area;
}

} // namespace

double intersection_area(const LayerData& d, const Feature& first, const Feature& second, Pt* where)
{
    // GEOS's overlay is not symmetric to the last bit: a vertex within an ulp of the other's edge
    // gave 6.9e-18 m2 one way and 0 the other (Jakarta's FIDs 46507 and 46510), and a layer judged
    // against itself had a "new" overlap because the output's pair and the input's pair were
    // passed in opposite orders. One order for a pair, whoever asks: the lower FID first.
    const bool swap = second.fid < first.fid || (second.fid == first.fid && &second < &first);
    const Feature& fa = swap ? second : first;
    const Feature& fb = swap ? first : second;
    std::unique_ptr<OGRGeometry> ga(d.make_ogr_polygon(fa)), gb(d.make_ogr_polygon(fb));
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::unique_ptr<OGRGeometry> inter(ga->Intersection(gb.get()));
    if (!inter) { // invalid operands (counted as invalid already): measure their repaired forms
        std::unique_ptr<OGRGeometry> va(ga->MakeValid()), vb(gb->MakeValid());
        if (va && vb) {
            inter.reset(va->Intersection(vb.get()));
        }
    }
    CPLPopErrorHandler();
    if (!inter || inter->IsEmpty()) {
        return 0;
    }
    const double area = surface_area(*inter);
    OGRPoint centroid;
    if (area > 0 && inter->Centroid(&centroid) == OGRERR_NONE) {
        *where = {centroid.getX(), centroid.getY()};
    }
    return area;
}

double overlap_area(const LayerData& d, const std::vector<std::int8_t>& interior_left,
                    const std::vector<std::uint8_t>& invalid, std::uint32_t i, std::uint32_t j, Pt* where)
{
    const Feature& fa = d.features[i];
    const Feature& fb = d.features[j];
    const bool valid = !invalid[i] && !invalid[j];
    if (valid && interiors_meet(d, interior_left, fa, fb) == OverlapVerdict::disjoint) {
        return 0;
    }
    return intersection_area(d, fa, fb, where);
}

bool interiors_overlap(const LayerData& d, const std::vector<std::int8_t>& interior_left,
                       const std::vector<std::uint8_t>& invalid, std::uint32_t i, std::uint32_t j)
{
    if (!invalid[i] && !invalid[j]) {
        const OverlapVerdict verdict = interiors_meet(d, interior_left, d.features[i], d.features[j]);
        if (verdict != OverlapVerdict::unknown) {
            return verdict == OverlapVerdict::overlap;
        }
    }
    Pt unused;
    return intersection_area(d, d.features[i], d.features[j], &unused) > 0;
}

PolygonIndex index_polygons(const LayerData& d, const std::vector<std::uint32_t>& candidates)
{
    PolygonIndex index;
    std::vector<Box> boxes;
    const std::size_t n = candidates.empty() ? d.features.size() : candidates.size();
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i = candidates.empty() ? static_cast<std::uint32_t>(k) : candidates[k];
        if (d.features[i].kind == FeatureKind::polygon) {
            index.ids.push_back(i);
            boxes.push_back(d.features[i].box);
        }
    }
    index.tree.build(std::move(boxes));
    return index;
}

namespace {

/// The outputs of input features i and j when both are polygons and share no boundary.
bool outputs_lost_boundary(const Context& c, std::uint32_t i, std::uint32_t j)
{
    const Feature& oi = c.b.features[static_cast<std::size_t>(c.match[i])];
    const Feature& oj = c.b.features[static_cast<std::size_t>(c.match[j])];
    if (oi.kind != FeatureKind::polygon || oj.kind != FeatureKind::polygon) {
        return false;
    }
    Pt unused;
    return !oi.box.intersects(oj.box) || shared_length(c.b, oi, oj, &unused) <= 0;
}

} // namespace

void measure_gaps(const Context& c, AssessReport& r)
{
    const PolygonIndex index = index_polygons(c.a);
    tbb::combinable<std::vector<AssessExample>> found;
    tbb::combinable<std::int64_t> shared;
    for_candidate_pairs(index, false, [&](std::uint32_t i, std::uint32_t j) {
        Pt where;
        const double length = shared_length(c.a, c.a.features[i], c.a.features[j], &where);
        if (length <= 2 * c.tolerance) {
            return;
        }
        ++shared.local();
        if (c.match[i] < 0 || c.match[j] < 0 || !outputs_lost_boundary(c, i, j)) {
            return; // a lost feature is counted as missing
        }
        const std::int64_t fa = std::min(c.a.features[i].fid, c.a.features[j].fid);
        const std::int64_t fb = std::max(c.a.features[i].fid, c.a.features[j].fid);
        AssessExample e = example_at(fa, fb, where, length);
        e.excused_by = c.excuses.explain(Defect::gap, fa, fb);
        found.local().push_back(std::move(e));
    });
    r.n_shared_in = shared.combine(std::plus<>());
    std::vector<AssessExample> all;
    found.combine_each([&](const auto& v) { all.insert(all.end(), v.begin(), v.end()); });
    r.gaps_new = static_cast<std::int64_t>(all.size());
    for (const AssessExample& e : all) {
        if (!e.excused_by.empty()) {
            ++r.excused_counts.gaps;
            note_excused(r, e, "new gap");
        }
    }
    keep_first(all, c.k, by_fids);
    r.gaps_new_examples = std::move(all);
}

} // namespace trisnap::assess
