// The measurements behind `trisnap render` on hand-made layers with known answers: collapses,
// drift, closest vertex–vertex and vertex–edge pairs (shared boundaries counted once), the
// grid index against brute force, and the choice of worst sites.
#include "render/grid_index.hpp"
#include "render/sites.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace trisnap::render {
namespace {

Shape square(std::int64_t key, double x0, double y0, double x1, double y1)
{
    Shape s;
    s.key = key;
    s.rings = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}};
    for (XY p : s.rings[0]) s.box.add(p);
    return s;
}

Layer layer_of(std::vector<Shape> shapes)
{
    Layer layer;
    for (const Shape& s : shapes) layer.extent.add(s.box);
    layer.shapes = std::move(shapes);
    return layer;
}

const Layer& out_of(const Shape& shape)
{
    static Layer layer;
    layer = layer_of({shape});
    return layer;
}

std::vector<Site> of_kind(const std::vector<Site>& sites, SiteKind kind)
{
    std::vector<Site> out;
    std::copy_if(sites.begin(), sites.end(), std::back_inserter(out), [&](const Site& s) { return s.kind == kind; });
    return out;
}

TEST(RenderSites, CollapseIsAnInputFeatureWithoutOutput)
{
    const Layer in = layer_of({square(1, 0, 0, 10, 10), square(2, 20, 0, 20.4, 0.2)});
    const Layer out = layer_of({square(1, 0, 0, 10, 10)});
    const auto sites = find_sites(in, &out, 1.0);
    const auto collapses = of_kind(sites, SiteKind::collapse);
    ASSERT_EQ(collapses.size(), 1u);
    EXPECT_EQ(collapses[0].fid, 2);
    EXPECT_TRUE(collapses[0].defect);
    EXPECT_DOUBLE_EQ(collapses[0].at.x, 20.2);
    EXPECT_NEAR(collapses[0].value, 2 * 0.08 / 1.2, 1e-12); // mean width 2A/P
    EXPECT_EQ(collapses[0].name, "width");
    EXPECT_TRUE(of_kind(sites, SiteKind::drift).empty()) << "an unchanged feature has no drift";
}

TEST(RenderSites, DriftIsTheLargestVertexDistanceEitherWay)
{
    Layer in = layer_of({square(1, 0, 0, 10, 10)});
    Layer out = in;
    out.shapes[0].rings[0][2] = {13, 10}; // (10,10) -> (13,10): 3 from the input's right edge
    const auto drift = of_kind(find_sites(in, &out, 1.0), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_DOUBLE_EQ(drift[0].value, 3.0);
    EXPECT_EQ(drift[0].at, (XY{13, 10}));
    EXPECT_EQ(drift[0].other, (XY{10, 10}));
    EXPECT_TRUE(drift[0].defect) << "3 > 2T";

    out.shapes[0].rings[0][2] = {11.5, 10};
    const auto small = of_kind(find_sites(in, &out, 1.0), SiteKind::drift);
    ASSERT_EQ(small.size(), 1u);
    EXPECT_DOUBLE_EQ(small[0].value, 1.5);
    EXPECT_FALSE(small[0].defect);
}

TEST(RenderSites, DriftSeesAVertexThatWasRemoved)
{
    Shape spike = square(1, 0, 0, 10, 10);
    spike.rings[0].insert(spike.rings[0].begin() + 2, XY{10, 5}); // (10,0) (10,5) (10,10)
    spike.rings[0][2] = {14, 5};                                   // a spike 4 long
    spike.box.add(XY{14, 5});
    const Layer in = layer_of({spike});
    const Layer out = layer_of({square(1, 0, 0, 10, 10)});
    const auto drift = of_kind(find_sites(in, &out, 1.0), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_DOUBLE_EQ(drift[0].value, 4.0);
    EXPECT_EQ(drift[0].other, (XY{14, 5})) << "the input vertex";
    EXPECT_EQ(drift[0].at, (XY{10, 5})) << "the nearest output point";
}

TEST(RenderSites, DriftBetweenFarApartFeaturesIsTheirDistance)
{
    // Matched by key but a million units apart (another tool's output, wrong keys): the
    // nearest-edge search must give up widening and scan, not visit ~10^12 empty cells.
    Shape dense;
    dense.key = 1;
    for (int i = 0; i <= 1000; ++i) dense.rings.push_back({{i * 0.001, 0}, {i * 0.001, 0.0005}});
    dense.polygon = false;
    for (const auto& r : dense.rings)
        for (XY p : r) dense.box.add(p);
    Shape far = dense;
    for (auto& r : far.rings)
        for (XY& p : r) p.y += 1e6;
    far.box = Box{0, 1e6, 1, 1e6 + 0.0005};
    const auto drift = of_kind(find_sites(layer_of({dense}), &out_of(far), 1.0), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_NEAR(drift[0].value, 1e6, 1e-6);
}

TEST(RenderSites, ClosePairsCountSharedBoundariesOnce)
{
    // Two squares sharing an edge (not a defect) and a third 0.4 to the right of the second.
    const Layer out = layer_of({square(1, 0, 0, 10, 10), square(2, 10, 0, 20, 10), square(3, 20.4, 0, 30, 10)});
    const auto sites = find_sites(out, nullptr, 1.0);
    const auto vv = of_kind(sites, SiteKind::vertex_vertex);
    const auto ve = of_kind(sites, SiteKind::vertex_edge);
    ASSERT_EQ(vv.size(), 2u); // (20,0)-(20.4,0) and (20,10)-(20.4,10)
    for (const Site& s : vv) {
        EXPECT_NEAR(s.value, 0.4, 1e-12);
        EXPECT_TRUE(s.defect);
        EXPECT_EQ(s.at.x, 20.0);
        EXPECT_EQ(s.fid, 2);
        EXPECT_EQ(s.fid2, 3);
    }
    ASSERT_EQ(ve.size(), 4u); // each of the four corners facing the gap, to the other side's edge
    for (const Site& s : ve) {
        EXPECT_NEAR(s.value, 0.4, 1e-12);
        EXPECT_TRUE(s.defect) << "0.4 < T/2";
    }
}

TEST(RenderSites, VertexOnAnEdgeItDoesNotEndIsAtDistanceZero)
{
    Shape tee;
    tee.key = 7;
    tee.polygon = false;
    tee.rings = {{{0, 0}, {10, 0}}, {{5, 0}, {5, 5}}};
    for (const auto& r : tee.rings)
        for (XY p : r) tee.box.add(p);
    const auto ve = of_kind(find_sites(layer_of({tee}), nullptr, 1.0), SiteKind::vertex_edge);
    ASSERT_EQ(ve.size(), 1u);
    EXPECT_EQ(ve[0].at, (XY{5, 0}));
    EXPECT_EQ(ve[0].value, 0.0);
}

TEST(RenderSites, NoPairsWithoutATolerance)
{
    const Layer out = layer_of({square(1, 0, 0, 10, 10), square(3, 10.1, 0, 30, 10)});
    EXPECT_TRUE(find_sites(out, nullptr, std::nullopt).empty());
}

TEST(RenderSites, WorstTakesBreachesFirstAndEveryKindInTurn)
{
    std::vector<Site> sites;
    auto add = [&](SiteKind kind, double x, double value, bool defect) {
        Site s;
        s.kind = kind;
        s.at = s.other = {x, 0};
        s.value = value;
        s.defect = defect;
        sites.push_back(s);
    };
    add(SiteKind::drift, 0, 5, true);
    add(SiteKind::drift, 100, 4, true);
    add(SiteKind::drift, 200, 1, false);
    add(SiteKind::vertex_edge, 300, 0.1, true);
    add(SiteKind::vertex_edge, 300.5, 0.2, true); // too close to the one before
    add(SiteKind::vertex_vertex, 400, 2, false);
    const auto worst = pick_worst(sites, 4, 3.0);
    ASSERT_EQ(worst.size(), 4u);
    EXPECT_EQ(worst[0].at.x, 0);   // drift breach
    EXPECT_EQ(worst[1].at.x, 300); // vertex-edge breach
    EXPECT_EQ(worst[2].at.x, 100); // second drift breach
    EXPECT_EQ(worst[3].at.x, 200); // then the rest, kinds in turn
    EXPECT_EQ(pick_worst(sites, 10, 3.0).size(), 5u) << "one site is skipped as a near duplicate";
}

TEST(RenderGrid, SegmentQueriesFindEverythingBruteForceFinds)
{
    std::mt19937 random(42);
    std::uniform_real_distribution<double> coord(0, 100), step(-8, 8);
    std::vector<Segment> segments;
    for (int i = 0; i < 2000; ++i) {
        const XY a{coord(random), coord(random)};
        segments.push_back({a, {a.x + step(random), a.y + step(random)}});
    }
    const GridIndex grid(segments, GridIndex::cell_for(segments, 1.0));
    for (int q = 0; q < 200; ++q) {
        const XY p{coord(random), coord(random)};
        const double r = 0.5 + q % 5;
        std::vector<std::uint32_t> found, expected;
        grid.visit(p, r, [&](std::uint32_t i) {
            if (distance_to_segment(p, segments[i].a, segments[i].b) <= r) found.push_back(i);
        });
        for (std::uint32_t i = 0; i < segments.size(); ++i)
            if (distance_to_segment(p, segments[i].a, segments[i].b) <= r) expected.push_back(i);
        std::sort(found.begin(), found.end());
        found.erase(std::unique(found.begin(), found.end()), found.end());
        ASSERT_EQ(found, expected) << "query " << q;
    }
}

} // namespace
} // namespace trisnap::render
