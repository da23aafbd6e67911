// assess on GEOS output with real defects: GEOSGeom_setPrecision per feature on a window of the
// Andorra layer, at a coarse grid so neighbours snapped independently cross and overlap. An
// independent GEOS count (DE-9IM relate on segments, intersection areas on polygon pairs,
// GEOSisValid) must agree with what assess finds. Brute force is fine on a few hundred features.
#include "assess_fixture.hpp"
#include "test_data.hpp"

#include <geos_c.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <array>
#include <functional>
#include <iterator>
#include <iostream>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

namespace trisnap::test {
namespace {

struct Geos {
    Geos() { h = GEOS_init_r(); }
    ~Geos() { GEOS_finish_r(h); }
    GEOSContextHandle_t h;
};

struct Layers {
    GDALDatasetUniquePtr in, out;
    std::vector<std::string> in_wkt, out_wkt; // per feature; output "" when empty
    int empty = 0;
};

/// The window's features as read, and each one through GEOSGeom_setPrecision at grid t.
Layers snap_with_geos(Geos& geos, const std::string& path, double t)
{
    GDALAllRegister();
    GDALDatasetUniquePtr src(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    if (!src) throw std::runtime_error("cannot open " + path);
    OGRLayer* layer = src->GetLayer(0);
    layer->SetSpatialFilterRect(1.50, 42.49, 1.54, 42.52);
    std::vector<Item> in, out;
    Layers result;
    GEOSWKTReader* reader = GEOSWKTReader_create_r(geos.h);
    GEOSWKTWriter* writer = GEOSWKTWriter_create_r(geos.h);
    GEOSWKTWriter_setTrim_r(geos.h, writer, 1);
    GEOSWKTWriter_setRoundingPrecision_r(geos.h, writer, 17);
    for (OGRFeatureUniquePtr f{layer->GetNextFeature()}; f; f.reset(layer->GetNextFeature())) {
        char* wkt = nullptr;
        f->GetGeometryRef()->exportToWkt(&wkt, wkbVariantIso);
        in.push_back({f->GetFID(), wkt, f->GetFieldAsString(0)});
        GEOSGeometry* g = GEOSWKTReader_read_r(geos.h, reader, wkt);
        CPLFree(wkt);
        GEOSGeometry* snapped = GEOSGeom_setPrecision_r(geos.h, g, t, 0);
        std::string snapped_wkt;
        if (snapped && !GEOSisEmpty_r(geos.h, snapped)) {
            char* s = GEOSWKTWriter_write_r(geos.h, writer, snapped);
            snapped_wkt = s;
            GEOSFree_r(geos.h, s);
        } else {
            ++result.empty;
        }
        if (snapped) GEOSGeom_destroy_r(geos.h, snapped);
        GEOSGeom_destroy_r(geos.h, g);
        out.push_back({in.back().fid, snapped_wkt, in.back().name});
        result.out_wkt.push_back(snapped_wkt);
        result.in_wkt.push_back(in.back().wkt);
    }
    GEOSWKTReader_destroy_r(geos.h, reader);
    GEOSWKTWriter_destroy_r(geos.h, writer);
    result.in = make_layer(in);
    result.out = make_layer(out);
    return result;
}

using GeomList = std::vector<GEOSGeometry*>;

/// Distinct segments of all outputs as 2-point GEOS lines.
GeomList distinct_segments(Geos& geos, const GeomList& geoms)
{
    std::set<std::array<double, 4>> seen;
    const std::function<void(const GEOSGeometry*)> walk = [&](const GEOSGeometry* g) {
        const int type = GEOSGeomTypeId_r(geos.h, g);
        if (type == GEOS_POLYGON) {
            walk(GEOSGetExteriorRing_r(geos.h, g));
            for (int i = 0; i < GEOSGetNumInteriorRings_r(geos.h, g); ++i) walk(GEOSGetInteriorRingN_r(geos.h, g, i));
        } else if (type == GEOS_LINESTRING || type == GEOS_LINEARRING) {
            const GEOSCoordSequence* cs = GEOSGeom_getCoordSeq_r(geos.h, g);
            unsigned n = 0;
            GEOSCoordSeq_getSize_r(geos.h, cs, &n);
            for (unsigned i = 0; i + 1 < n; ++i) {
                double x0, y0, x1, y1;
                GEOSCoordSeq_getXY_r(geos.h, cs, i, &x0, &y0);
                GEOSCoordSeq_getXY_r(geos.h, cs, i + 1, &x1, &y1);
                if (x0 == x1 && y0 == y1) continue;
                std::array<double, 4> s{x0, y0, x1, y1};
                if (std::make_pair(x1, y1) < std::make_pair(x0, y0)) s = {x1, y1, x0, y0};
                seen.insert(s);
            }
        } else {
            for (int i = 0; i < GEOSGetNumGeometries_r(geos.h, g); ++i) walk(GEOSGetGeometryN_r(geos.h, g, i));
        }
    };
    for (const GEOSGeometry* g : geoms) walk(g);
    GeomList segments;
    for (const auto& s : seen) {
        GEOSCoordSequence* cs = GEOSCoordSeq_create_r(geos.h, 2, 2);
        GEOSCoordSeq_setXY_r(geos.h, cs, 0, s[0], s[1]);
        GEOSCoordSeq_setXY_r(geos.h, cs, 1, s[2], s[3]);
        segments.push_back(GEOSGeom_createLineString_r(geos.h, cs));
    }
    return segments;
}

/// Pairs of distinct segments that meet other than at a shared endpoint, by DE-9IM: two
/// segments touching only at a common endpoint relate as FF*F0****.
int count_crossings(Geos& geos, const GeomList& segments)
{
    GEOSSTRtree* tree = GEOSSTRtree_create_r(geos.h, 10);
    for (std::size_t i = 0; i < segments.size(); ++i) GEOSSTRtree_insert_r(geos.h, tree, segments[i], (void*)(i));
    int crossings = 0;
    struct Ctx {
        Geos* geos;
        const GeomList* segments;
        std::size_t i;
        int* crossings;
    };
    for (std::size_t i = 0; i < segments.size(); ++i) {
        Ctx ctx{&geos, &segments, i, &crossings};
        GEOSSTRtree_query_r(geos.h, tree, segments[i], [](void* item, void* data) {
            auto* c = static_cast<Ctx*>(data);
            const auto j = reinterpret_cast<std::size_t>(item);
            if (j <= c->i) return;
            const GEOSGeometry* a = (*c->segments)[c->i];
            const GEOSGeometry* b = (*c->segments)[j];
            if (GEOSIntersects_r(c->geos->h, a, b) == 1 && GEOSRelatePattern_r(c->geos->h, a, b, "FF*F0****") != 1)
                ++*c->crossings;
        }, &ctx);
    }
    GEOSSTRtree_destroy_r(geos.h, tree);
    return crossings;
}

/// Pairs (by position; null geometries skipped) of polygons whose intersection has positive
/// area, and the total of those areas. All pairs: a thousand features.
std::pair<std::set<std::pair<std::size_t, std::size_t>>, double> overlapping_pairs(Geos& geos, const GeomList& geoms)
{
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    double area = 0;
    for (std::size_t i = 0; i < geoms.size(); ++i)
        for (std::size_t j = i + 1; j < geoms.size(); ++j) {
            if (!geoms[i] || !geoms[j] || GEOSIntersects_r(geos.h, geoms[i], geoms[j]) != 1) continue;
            GEOSGeometry* inter = GEOSIntersection_r(geos.h, geoms[i], geoms[j]);
            double a = 0;
            if (inter) GEOSArea_r(geos.h, inter, &a), GEOSGeom_destroy_r(geos.h, inter);
            if (a > 0) pairs.insert({i, j}), area += a;
        }
    return {pairs, area};
}

/// One GEOS geometry per WKT, null for "".
GeomList read_all(Geos& geos, const std::vector<std::string>& wkts)
{
    GEOSWKTReader* reader = GEOSWKTReader_create_r(geos.h);
    GeomList geoms;
    for (const std::string& wkt : wkts) geoms.push_back(wkt.empty() ? nullptr : GEOSWKTReader_read_r(geos.h, reader, wkt.c_str()));
    GEOSWKTReader_destroy_r(geos.h, reader);
    return geoms;
}

TEST(AssessGeos, FindsWhatAnIndependentGeosCountFinds)
{
    const auto path = shared_data("snapoly_andorra/andorra.gpkg");
    if (!path) GTEST_SKIP() << "../shared/data/snapoly_andorra/andorra.gpkg is absent";
    Geos geos;
    const double t = 2e-5; // about 2 m: coarse enough that independent per-feature snapping breaks things
    Layers layers = snap_with_geos(geos, *path, t);
    const AssessReport r = assess_layers({*layers.in, *layers.in->GetLayer(0)}, {*layers.out, *layers.out->GetLayer(0)},
                                         AssessOptions{t, "", 20});
    ASSERT_GT(r.n_in, 100);

    GeomList geoms = read_all(geos, layers.out_wkt), inputs = read_all(geos, layers.in_wkt);
    int invalid = 0;
    for (const GEOSGeometry* g : geoms) invalid += g && GEOSisValid_r(geos.h, g) != 1;
    GeomList present;
    std::copy_if(geoms.begin(), geoms.end(), std::back_inserter(present), [](auto* g) { return g != nullptr; });
    GeomList segments = distinct_segments(geos, present);
    const int crossings = count_crossings(geos, segments);
    const auto [pairs, overlap_area] = overlapping_pairs(geos, geoms);
    const auto input_pairs = overlapping_pairs(geos, inputs).first;
    const int overlaps = static_cast<int>(pairs.size());
    const int overlaps_new = static_cast<int>(std::count_if(pairs.begin(), pairs.end(), [&](const auto& p) { return !input_pairs.count(p); }));

    std::cout << "[ info     ] GEOS at grid " << t << ": " << r.n_in << " features, " << crossings << " crossings, "
              << overlaps << " overlaps (" << overlaps_new << " new), " << invalid << " invalid, " << layers.empty << " empty; assess: "
              << r.n_crossings << ", " << r.n_overlaps << ", " << r.n_invalid << ", " << r.n_empty
              << "; min vertex-edge " << r.min_vertex_edge.value_or(-1) / t << " T\n";
    EXPECT_EQ(r.n_missing, layers.empty);
    EXPECT_EQ(r.n_empty, layers.empty);
    EXPECT_EQ(r.n_invalid, invalid);
    EXPECT_EQ(r.n_crossings, crossings);
    EXPECT_EQ(r.n_overlaps, overlaps);
    EXPECT_EQ(r.n_overlaps_new, overlaps_new);
    EXPECT_NEAR(r.overlap_area, overlap_area, 1e-9 * std::max(1e-12, overlap_area) + 1e-20);
    // GEOS's per-feature snapping is known to break the contract here; the counts above must be real.
    EXPECT_GT(r.n_crossings + r.n_overlaps, 0) << "the window should show GEOS defects";
    EXPECT_FALSE(r.contract_holds());
    // Hausdorff: GEOS's discrete Hausdorff on densified boundaries is a lower bound of the true
    // value (assess is exact to T/1000) and close to it.
    double geos_max = 0;
    for (std::size_t i = 0; i < layers.in_wkt.size(); ++i) {
        if (layers.out_wkt[i].empty()) continue;
        GEOSWKTReader* rd = GEOSWKTReader_create_r(geos.h);
        GEOSGeometry* a = GEOSWKTReader_read_r(geos.h, rd, layers.in_wkt[i].c_str());
        GEOSGeometry* b = GEOSWKTReader_read_r(geos.h, rd, layers.out_wkt[i].c_str());
        GEOSGeometry* ba = GEOSBoundary_r(geos.h, a);
        GEOSGeometry* bb = GEOSBoundary_r(geos.h, b);
        double d = 0;
        GEOSHausdorffDistanceDensify_r(geos.h, ba, bb, 0.02, &d);
        geos_max = std::max(geos_max, d);
        for (GEOSGeometry* g : {a, b, ba, bb}) GEOSGeom_destroy_r(geos.h, g);
        GEOSWKTReader_destroy_r(geos.h, rd);
    }
    EXPECT_LE(geos_max, r.max_hausdorff + 1e-3 * t + 1e-15);
    EXPECT_GE(geos_max, 0.9 * r.max_hausdorff);
    for (GEOSGeometry* g : geoms) if (g) GEOSGeom_destroy_r(geos.h, g);
    for (GEOSGeometry* g : inputs) if (g) GEOSGeom_destroy_r(geos.h, g);
    for (GEOSGeometry* g : segments) GEOSGeom_destroy_r(geos.h, g);
}

} // namespace
} // namespace trisnap::test

namespace trisnap::test {
namespace {

/// Distinct vertices and distinct segments of a layer, read straight from OGR.
void collect(OGRLayer& layer, std::vector<std::pair<double, double>>& vertices,
             std::vector<std::array<double, 4>>& segments)
{
    std::set<std::pair<double, double>> vs;
    std::set<std::array<double, 4>> ss;
    layer.ResetReading();
    for (OGRFeatureUniquePtr f{layer.GetNextFeature()}; f; f.reset(layer.GetNextFeature())) {
        std::unique_ptr<OGRGeometry> boundary(f->GetGeometryRef()->Boundary());
        const std::function<void(const OGRGeometry&)> walk = [&](const OGRGeometry& g) {
            if (const auto* line = dynamic_cast<const OGRSimpleCurve*>(&g)) {
                for (int i = 0; i < line->getNumPoints(); ++i) {
                    vs.insert({line->getX(i), line->getY(i)});
                    if (i == 0) continue;
                    std::pair<double, double> p{line->getX(i - 1), line->getY(i - 1)}, q{line->getX(i), line->getY(i)};
                    if (p == q) continue;
                    if (q < p) std::swap(p, q);
                    ss.insert({p.first, p.second, q.first, q.second});
                }
            } else if (const auto* c = dynamic_cast<const OGRGeometryCollection*>(&g)) {
                for (const OGRGeometry* member : *c) walk(*member);
            }
        };
        walk(*boundary);
    }
    vertices.assign(vs.begin(), vs.end());
    segments.assign(ss.begin(), ss.end());
}

/// Distance from (x, y) to a segment, by the projection written out here (not assess's code).
double to_segment(double x, double y, const std::array<double, 4>& s)
{
    const double ux = s[2] - s[0], uy = s[3] - s[1];
    double t = ((x - s[0]) * ux + (y - s[1]) * uy) / (ux * ux + uy * uy);
    t = std::max(0.0, std::min(1.0, t));
    return std::hypot(x - (s[0] + t * ux), y - (s[1] + t * uy));
}

TEST(AssessRealData, SeparationsMatchBruteForce)
{
    const auto path = shared_data("snapoly_andorra/andorra.gpkg");
    if (!path) GTEST_SKIP() << "../shared/data/snapoly_andorra/andorra.gpkg is absent";
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GDALDataset::Open(path->c_str(), GDAL_OF_VECTOR));
    ASSERT_TRUE(ds);
    OGRLayer& layer = *ds->GetLayer(0);
    layer.SetSpatialFilterRect(1.50, 42.49, 1.53, 42.51);
    const AssessReport r = assess_layers({*ds, layer}, {*ds, layer}, AssessOptions{1e-6, "", 20});
    std::vector<std::pair<double, double>> v;
    std::vector<std::array<double, 4>> s;
    collect(layer, v, s);
    ASSERT_GT(v.size(), 1000u);
    double vv = std::numeric_limits<double>::infinity(), ve = vv;
    for (std::size_t i = 0; i < v.size(); ++i) {
        for (std::size_t j = i + 1; j < v.size(); ++j)
            vv = std::min(vv, std::hypot(v[i].first - v[j].first, v[i].second - v[j].second));
        for (const auto& seg : s) {
            const bool incident = (seg[0] == v[i].first && seg[1] == v[i].second) ||
                                  (seg[2] == v[i].first && seg[3] == v[i].second);
            if (!incident) ve = std::min(ve, to_segment(v[i].first, v[i].second, seg));
        }
    }
    ASSERT_TRUE(r.min_vertex_vertex && r.min_vertex_edge);
    EXPECT_NEAR(*r.min_vertex_vertex, vv, 1e-15);
    EXPECT_NEAR(*r.min_vertex_edge, ve, 1e-15);
    EXPECT_LT(ve, 1e-6) << "this window has a vertex closer than T to an edge";
}

} // namespace
} // namespace trisnap::test
