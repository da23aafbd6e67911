// 2.5D input: Z rides along. A vertex that does not move keeps its Z, merged vertices take the
// mean of their defined Zs, and a vertex created on an edge takes the Z interpolated along it.
#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

namespace trisnap {
namespace {

constexpr double t = 1.0;

Feature feature(std::int64_t id, const std::string& wkt) { return {id, read_wkt(wkt)}; }

/// The Z of the output vertex at (x, y) of `g`, if it has one there.
std::optional<double> z_at(const Geometry& g, double x, double y) {
    auto find = [&](const Path& p) -> std::optional<double> {
        for (const Coord& c : p)
            if (std::abs(c.x - x) < 1e-9 && std::abs(c.y - y) < 1e-9)
                return c.z;
        return std::nullopt;
    };
    for (const Polygon& poly : g.polygons)
        for (const Path& r : poly.rings)
            if (auto z = find(r))
                return z;
    for (const Path& l : g.lines)
        if (auto z = find(l))
            return z;
    return std::nullopt;
}

TEST(Z, SquarePairThatNeedsNoSnappingKeepsEveryZ) {
    const std::vector<Feature> in = {
        feature(1, "POLYGON Z ((0 0 1, 10 0 2, 10 10 3, 0 10 4, 0 0 1))"),
        feature(2, "POLYGON Z ((10 0 2, 20 0 5, 20 10 6, 10 10 3, 10 0 2))")};
    const CheckedRun run = snap_and_check(in, options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    for (std::size_t i = 0; i < in.size(); ++i) {
        EXPECT_TRUE(run.result.features[i].geometry.has_z);
        EXPECT_EQ(to_wkt(run.result.features[i].geometry), to_wkt(in[i].geometry));
    }
}

TEST(Z, MergedVerticesTakeTheMeanZ) {
    // Corners 0.4 apart merge at their midpoint: Z (2 + 4) / 2 = 3 on both sides.
    const std::vector<Feature> in = {
        feature(1, "POLYGON Z ((0 0 0, 10 0 0, 10 10 2, 0 10 0, 0 0 0))"),
        feature(2, "POLYGON Z ((10.4 10 4, 20 10 0, 20 20 0, 10.4 20 0, 10.4 10 4))")};
    const CheckedRun run = snap_and_check(in, options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    for (const FeatureOutput& f : run.result.features) {
        const auto z = z_at(f.geometry, 10.2, 10);
        ASSERT_TRUE(z.has_value()) << to_wkt(f.geometry);
        EXPECT_DOUBLE_EQ(*z, 3.0) << to_wkt(f.geometry);
    }
}

TEST(Z, MergeIgnoresAMissingZ) {
    // A 2D polygon beside a 2.5D one: the merged corners keep the only Z there is.
    const SnapResult r = snap({feature(1, "POLYGON Z ((0 0 0, 10 0 0, 10 10 10, 0 10 10, 0 0 0))"),
                               feature(2, "POLYGON ((10.3 0, 20 0, 20 10, 10.3 10, 10.3 0))")},
                              options_at(t));
    EXPECT_EQ(z_at(r.features[0].geometry, 10.15, 10), std::optional<double>(10.0));
    EXPECT_FALSE(r.features[1].geometry.has_z);
}

TEST(Z, CrossingSplitsAPolygonEdgeAtItsInterpolatedZ) {
    // A 2D line crosses the edge (10 0 0)-(10 10 10) at (10 5): the polygon's new vertex lies
    // on its own edge, so its Z is that edge's interpolation, 5 (a line without Z has none).
    const CheckedRun run = snap_and_check({feature(1, "POLYGON Z ((0 0 0, 10 0 0, 10 10 10, 0 10 10, 0 0 0))"),
                                           feature(2, "LINESTRING (-5 5, 15 5)")},
                                          options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    const Geometry& poly = run.result.features[0].geometry;
    EXPECT_EQ(z_at(poly, 10, 5), std::optional<double>(5.0)) << to_wkt(poly);
    EXPECT_EQ(z_at(poly, 0, 5), std::optional<double>(5.0)) << to_wkt(poly);
}

TEST(Z, CrossingOfTwo25DLinesTakesTheMeanOfBothInterpolations) {
    // At (5 5) line 1 interpolates Z 15 and line 2 Z 10. They share one vertex there, so the
    // only order-free answer consistent with merges is the mean, 12.5, on both lines.
    const SnapResult r = snap({feature(1, "LINESTRING Z (0 0 0, 10 10 30)"),
                               feature(2, "LINESTRING Z (0 10 0, 10 0 20)")},
                              options_at(t));
    EXPECT_EQ(z_at(r.features[0].geometry, 5, 5), std::optional<double>(12.5)) << to_wkt(r.features[0].geometry);
    EXPECT_EQ(z_at(r.features[1].geometry, 5, 5), std::optional<double>(12.5)) << to_wkt(r.features[1].geometry);
}

TEST(Z, ThreeEdgesThroughAVertexAddTheirZInInputOrderWhateverTheTriangulation) {
    // At (5 5) the lines interpolate 1e16, -1e16 and 1. In input order the sum is 0 + 1, the
    // mean 1/3; in another order 1e16 + 1 rounds to 1e16 and the mean is 0. The walk round the
    // vertex starts at whatever face CGAL keeps for it, which other features nearby (another
    // tile's point set) change: the sum must not follow it.
    const std::vector<Feature> lines = {feature(1, "LINESTRING Z (0 0 2e16, 10 10 0)"),
                                        feature(2, "LINESTRING Z (0 10 -2e16, 10 0 0)"),
                                        feature(3, "LINESTRING Z (0 5 2, 10 5 0)")};
    for (int extra = 0; extra < 24; ++extra) {
        std::vector<Feature> in = lines;
        for (int k = 0; k < extra; ++k) {
            // Small triangles in the two gaps between the lines (45-135 and 225-315 degrees), 2.6
            // to 4 from the crossing: more than t from every line, near enough to change its star.
            const double a = (k % 2 ? 1.25 : 0.25) * 3.14159265358979 + 0.3 + 0.4 * ((k * 7 + extra) % 5) / 4.0;
            const double d = 2.6 + 1.4 * ((k * 3 + extra) % 4) / 3.0;
            const double x = 5 + d * std::cos(a) - 0.1, y = 5 + d * std::sin(a) - 0.1;
            in.push_back(feature(10 + k, "POLYGON ((" + std::to_string(x) + " " + std::to_string(y) + ", " +
                                             std::to_string(x + 0.2) + " " + std::to_string(y) + ", " + std::to_string(x + 0.1) +
                                             " " + std::to_string(y + 0.2) + ", " + std::to_string(x) + " " +
                                             std::to_string(y) + "))"));
        }
        const SnapResult r = snap(in, options_at(t));
        for (int f = 0; f < 3; ++f) {
            EXPECT_EQ(z_at(r.features[f].geometry, 5, 5), std::optional<double>(1.0 / 3.0))
                << extra << " extra features: " << to_wkt(r.features[f].geometry);
        }
    }
}

TEST(Z, VertexSnappedOntoAnEdgeSharesOneZWithIt) {
    // The vertex (10.3 5 7) moves onto the edge (10 0 0)-(10 10 10) where that edge
    // interpolates 5: both polygons carry the same vertex, with the mean 6.
    const CheckedRun run = snap_and_check({feature(1, "POLYGON Z ((0 0 0, 10 0 0, 10 10 10, 0 10 10, 0 0 0))"),
                                           feature(2, "POLYGON Z ((10.3 5 7, 20 0 0, 20 10 0, 10.3 5 7))")},
                                          options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    EXPECT_EQ(z_at(run.result.features[0].geometry, 10, 5), std::optional<double>(6.0));
    EXPECT_EQ(z_at(run.result.features[1].geometry, 10, 5), std::optional<double>(6.0));
}

TEST(Z, GridRoundingKeepsZ) {
    SnapOptions o = options_at(t, t / 10);
    const SnapResult r = snap({feature(1, "POLYGON Z ((0.01 0.02 1, 10.03 0 2, 10 10.04 3, 0 10 4, 0.01 0.02 1))")}, o);
    ASSERT_TRUE(r.features[0].geometry.has_z);
    EXPECT_EQ(z_at(r.features[0].geometry, 0, 0), std::optional<double>(1.0)) << to_wkt(r.features[0].geometry);
}

} // namespace
} // namespace trisnap
