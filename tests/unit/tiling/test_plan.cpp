// The tile plan (one owner per point, balanced by vertex count, regular grids anchored at
// multiples of the size) and the tile input (rings cut and closed outside the tile keep the
// membership of every point of the tile).
#include "generators.hpp"
#include "stitch/spool.hpp"
#include "tiling/plan.hpp"
#include "tiling/tile_input.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace trisnap {
namespace {

using tiling::Box;

bool in_region(const Region& r, double x, double y) { return r.contains(x, y); }

// A closed ring 4 wide that winds twice round the origin from radius `inner` outwards, `steps`
// points along each side.
Path spiral_band(double inner, int steps)
{
    Path ring;
    for (int i = 0; i <= steps; ++i) {
        const double a = 4 * M_PI * i / steps, r = inner + 10 * a;
        ring.push_back({r * std::cos(a), r * std::sin(a)});
    }
    for (int i = steps; i >= 0; --i) {
        const double a = 4 * M_PI * i / steps, r = inner + 4 + 10 * a;
        ring.push_back({r * std::cos(a), r * std::sin(a)});
    }
    ring.push_back(ring.front());
    return ring;
}

// A cut is not made where each half would take more than 3/4 of the tile's vertices once the
// other half's band within the halo of the cut is added (PlanOptions::halo): a 300 x 300
// coverage of 10-wide cells cut into tiles of <= 400 vertices is many tiles at a halo of 2, and
// at a halo of 80 (more than a quarter of the layer on each side of a cut) the first cut already
// copies more than that, so the plan is one tile. At 40 the cuts of 150-wide tiles are not made,
// and the tiles with their halos hold fewer copies of the vertices than the plan by count.
TEST(TilePlan, NoCutThatOnlyCopiesItsHaloBand)
{
    const auto features = perturbed_grid_coverage(30, 30, 10.0, 0.2, 1);
    tiling::PlanOptions o;
    o.vertex_budget = 400;
    const std::size_t by_count = tiling::make_plan(features, o).size();
    o.halo = 2.0;
    EXPECT_EQ(tiling::make_plan(features, o).size(), by_count) << "a thin halo changes nothing";
    o.halo = 80.0;
    EXPECT_EQ(tiling::make_plan(features, o).size(), 1u);
    o.halo = 40.0; // cuts of the 300-long sides copy 13 %, of the 150-long ones 27 %
    const tiling::TilePlan plan = tiling::make_plan(features, o);
    EXPECT_GT(plan.size(), 1u);
    EXPECT_LT(plan.size(), by_count);
    // Each leaf with the vertices within the halo around its core, against the layer.
    std::vector<Coord> points;
    for (const Feature& f : features)
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& r : p.rings) points.insert(points.end(), r.begin(), r.end());
    const auto load = [&](const tiling::TilePlan& pl) {
        std::size_t n = 0;
        for (std::size_t k = 0; k < pl.size(); ++k) {
            const Region& c = pl.core(k);
            for (const Coord& q : points)
                n += q.x >= c.xmin - o.halo && q.x <= c.xmax + o.halo && q.y >= c.ymin - o.halo && q.y <= c.ymax + o.halo;
        }
        return n;
    };
    tiling::PlanOptions count_only = o;
    count_only.halo = 0;
    const std::size_t copies = load(plan), copies_by_count = load(tiling::make_plan(features, count_only));
    EXPECT_LT(copies, copies_by_count);
    EXPECT_LE(copies, 3 * points.size()) << copies_by_count << " by count";
}

TEST(TilePlan, EveryPointHasExactlyOneOwnerAndQueriesAgree)
{
    const auto features = perturbed_grid_coverage(30, 30, 10.0, 0.2, 1);
    tiling::PlanOptions o;
    o.vertex_budget = 400;
    const tiling::TilePlan plan = tiling::make_plan(features, o);
    ASSERT_GT(plan.size(), 8u);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 2000; ++i) {
        const double x = uniform(rng, -50, 350), y = uniform(rng, -50, 350);
        std::size_t owners = 0;
        for (std::size_t k = 0; k < plan.size(); ++k) owners += in_region(plan.core(k), x, y);
        ASSERT_EQ(owners, 1u) << x << " " << y;
        const std::size_t leaf = plan.leaf_of(x, y);
        EXPECT_TRUE(in_region(plan.core(leaf), x, y));
        std::vector<std::size_t> hits;
        plan.query(Box{x, y, x, y}, hits);
        EXPECT_NE(std::find(hits.begin(), hits.end(), leaf), hits.end());
    }
    // A split line belongs to the right/upper tile (half-open cores).
    const Region& c = plan.core(plan.leaf_of(150, 150));
    if (std::isfinite(c.xmin)) {
        EXPECT_EQ(plan.leaf_of(c.xmin, 150), plan.leaf_of(150, 150));
    }
}

// The sampled vertices serve only the plan; a run drops them right after it (up to 256 MiB).
// `xs = {}`, which the runs used before, assigns an empty initializer list and keeps the
// capacity: on Andorra x43 that held 51 MB through every later phase.
TEST(TilePlan, DroppingTheSampleFreesItsVerticesAndKeepsTheCounts)
{
    tiling::PlanInput in;
    in.extent = Box{0, 0, 10, 10};
    in.vertices = 5000;
    in.level = 2;
    in.xs.assign(1250, 1.0);
    in.ys.assign(1250, 2.0);
    in.drop_sample();
    EXPECT_EQ(in.xs.capacity(), 0u);
    EXPECT_EQ(in.ys.capacity(), 0u);
    EXPECT_EQ(in.vertices, 5000u);
    EXPECT_EQ(in.level, 2);
    EXPECT_EQ(in.extent.xmax, 10.0);
}

TEST(TilePlan, BalancedTilesRespectTheVertexBudget)
{
    const auto features = perturbed_grid_coverage(40, 40, 10.0, 0.2, 2);
    tiling::PlanOptions o;
    o.vertex_budget = 1000;
    const tiling::TilePlan plan = tiling::make_plan(features, o);
    std::vector<std::size_t> count(plan.size(), 0);
    std::size_t total = 0;
    for (const Feature& f : features)
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& r : p.rings)
                for (const Coord& q : r) ++count[plan.leaf_of(q.x, q.y)], ++total;
    EXPECT_EQ(total, plan.input_vertices());
    for (std::size_t k = 0; k < plan.size(); ++k) {
        EXPECT_LE(count[k], 1000u);
        EXPECT_EQ(plan.leaf_vertices(k), count[k]);
    }
    EXPECT_LE(plan.size(), 2 * total / 1000 + 2); // median splits: not needlessly many
}

TEST(TilePlan, RegularGridIsAnchoredAtMultiplesOfTheSize)
{
    const auto features = perturbed_grid_coverage(10, 10, 10.0, 0.2, 4);
    tiling::PlanOptions o;
    o.tile_size = 25;
    const tiling::TilePlan plan = tiling::make_plan(features, o);
    EXPECT_EQ(plan.size(), 25u); // extent 0..100: x = 100 opens a fifth column (half-open cores)
    for (std::size_t k = 0; k < plan.size(); ++k) {
        const Region& r = plan.core(k);
        for (double v : {r.xmin, r.xmax, r.ymin, r.ymax})
            if (std::isfinite(v)) {
                EXPECT_EQ(std::fmod(v, 25.0), 0.0);
            }
    }
    o.tile_size = 1e-4;
    EXPECT_THROW(tiling::make_plan(features, o), std::invalid_argument);
}

bool point_in_path(const Path& ring, double x, double y)
{
    bool in = false;
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Coord &a = ring[i], &b = ring[j];
        if ((a.y > y) != (b.y > y) && x < (b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x) in = !in;
    }
    return in;
}

bool inside(const Geometry& g, double x, double y)
{
    bool in = false;
    for (const Polygon& p : g.polygons)
        for (const Path& r : p.rings) in ^= point_in_path(r, x, y);
    return in;
}

// A spiral that winds twice round the tile, a C-shape around it, a ring enclosing it without
// touching it, and a hole: cut to the tile, every point of the tile keeps its membership.
TEST(TileInput, CutRingsKeepMembershipInsideTheTile)
{
    std::vector<Feature> features(3);
    const Path spiral = spiral_band(30, 400);
    features[0].id = 1;
    features[0].geometry.type = Geometry::Type::Polygon;
    features[0].geometry.polygons = {Polygon{{spiral}}};
    features[1].id = 2;
    features[1].geometry.type = Geometry::Type::Polygon;
    features[1].geometry.polygons = {Polygon{{{{-300, -300}, {300, -300}, {300, 300}, {-300, 300}, {-300, -300}},
                                              {{-5, -5}, {-5, 5}, {5, 5}, {5, -5}, {-5, -5}}}}};
    Path c_shape{{-60, -60}, {60, -60}, {60, -50}, {-50, -50}, {-50, 50}, {60, 50}, {60, 60}, {-60, 60}, {-60, -60}};
    features[2].id = 3;
    features[2].geometry.type = Geometry::Type::Polygon;
    features[2].geometry.polygons = {Polygon{{c_shape}}};
    std::vector<Problem> problems;
    const auto clean = detail::clean_input(features, 0.01, problems);
    const std::vector<bool> has_z(clean.size(), false);
    std::mt19937_64 rng(9);
    for (const Box R : {Box{20, -10, 45, 15}, Box{-8, -8, 8, 8}, Box{55, -20, 70, 20}, Box{-100, 80, 120, 140}}) {
        const tiling::TileInput in = tiling::build_tile_input(clean, has_z, {0, 1, 2}, R);
        ASSERT_EQ(in.features.size(), in.source.size());
        for (std::size_t k = 0; k < in.features.size(); ++k) {
            const Geometry& original = features[in.source[k]].geometry;
            for (int i = 0; i < 3000; ++i) {
                const double x = uniform(rng, R.xmin, R.xmax), y = uniform(rng, R.ymin, R.ymax);
                ASSERT_EQ(inside(in.features[k].geometry, x, y), inside(original, x, y))
                    << "feature " << in.features[k].id << " at " << x << " " << y;
            }
        }
        EXPECT_GE(in.features.size(), 1u); // the big square encloses every box
    }
}

// A tile's reach grows from r0 by both ends of every edge that meets r0, whatever rings lie
// wholly inside r0 or outside it (grow_reach skips those by their boxes): against every edge
// tried one by one, on islands inside, outside and across r0, a spiral and a line.
TEST(TileInput, ReachGrowsByTheEndsOfEveryEdgeMeetingR0)
{
    std::vector<Feature> features(2);
    std::vector<Polygon> islands;
    std::mt19937_64 rng(5);
    for (int k = 0; k < 60; ++k) {
        const double x = uniform(rng, -200, 200), y = uniform(rng, -200, 200), w = uniform(rng, 1, 30),
                     h = uniform(rng, 1, 30);
        islands.push_back(Polygon{{{{x, y}, {x + w, y}, {x + w, y + h}, {x + 0.3 * w, y + 1.4 * h}, {x, y + h}, {x, y}}}});
    }
    islands.push_back(Polygon{{spiral_band(230, 300)}});
    features[0].id = 1;
    features[0].geometry.type = Geometry::Type::MultiPolygon;
    features[0].geometry.polygons = islands;
    features[1].id = 2;
    features[1].geometry.type = Geometry::Type::LineString;
    features[1].geometry.lines = {{{-250, -40}, {-20, -35}, {10, 5}, {30, 260}, {300, 270}}};
    std::vector<Problem> problems;
    const auto clean = detail::clean_input(features, 0.01, problems);
    ASSERT_EQ(clean.size(), 2u);
    for (const Box r0 : {Box{-50, -50, 50, 50}, Box{0, 0, 120, 40}, Box{-210, -210, 210, 210}, Box{-300, 200, -200, 300},
                         Box{150, -20, 400, 20}}) {
        for (const auto& cf : clean) {
            Box expected = r0;
            std::size_t meeting = 0;
            auto edge = [&](const Coord& p, const Coord& q) {
                if (tiling::segment_meets_box(p, q, r0)) {
                    expected.add(p.x, p.y);
                    expected.add(q.x, q.y);
                    ++meeting;
                }
            };
            for (const auto& ring : cf.rings) {
                for (std::size_t i = 0; i < ring.points.size(); ++i) {
                    edge(ring.points[i], ring.points[(i + 1) % ring.points.size()]);
                }
            }
            for (const auto& line : cf.lines) {
                for (std::size_t i = 0; i + 1 < line.size(); ++i) {
                    edge(line[i], line[i + 1]);
                }
            }
            Box reach = r0;
            stitch::grow_reach(cf, stitch::box_of(cf), r0, reach);
            EXPECT_EQ(reach.xmin, expected.xmin) << cf.id << " " << meeting;
            EXPECT_EQ(reach.ymin, expected.ymin) << cf.id;
            EXPECT_EQ(reach.xmax, expected.xmax) << cf.id;
            EXPECT_EQ(reach.ymax, expected.ymax) << cf.id;
        }
    }
}

TEST(TileInput, LinesKeepTheirRunsThatMeetTheTile)
{
    std::vector<Feature> features(1);
    features[0].id = 7;
    features[0].geometry.type = Geometry::Type::LineString;
    features[0].geometry.lines = {{{0, 0}, {10, 0}, {20, 0}, {20, 10}, {0, 10}, {0, 20}, {30, 20}}};
    std::vector<Problem> problems;
    const auto clean = detail::clean_input(features, 0.01, problems);
    const tiling::TileInput in = tiling::build_tile_input(clean, {false}, {0}, Box{15, -1, 25, 1});
    ASSERT_EQ(in.features.size(), 1u);
    EXPECT_FALSE(in.intact[0]);
    ASSERT_EQ(in.features[0].geometry.lines.size(), 1u);
    const Path& part = in.features[0].geometry.lines[0];
    ASSERT_EQ(part.size(), 3u); // (10,0)-(20,0)-(20,10) meet the box; the other edges do not
    EXPECT_EQ(part[0].x, 10.0);
    EXPECT_EQ(part[2].x, 20.0);
    EXPECT_EQ(part[2].y, 10.0);
}

} // namespace
} // namespace trisnap
