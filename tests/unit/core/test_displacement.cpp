// FeatureOutput::max_displacement, the engine's per-feature drift bound (the report's
// max_displacement): every output vertex of a feature lies on the feature's output boundary,
// which runs along pieces of its own input edges, so the bound is at least the distance of every
// output vertex from the feature's input boundary. Measured here from input and output alone, by
// brute force, sharing nothing with the engine's evidence pass. The pass skips the ends of input
// edges that are still input points; a pass that skipped every deviation fails the
// near-degenerate case, but one that skipped every input point (not only the edge's own ends) is
// not caught: on these inputs such points lie on other features' edges only up to rounding.
// Also the overload of snap() that frees its input after cleaning gives the same result.
#include "snap_harness.hpp"

#include "generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace trisnap {
namespace {

using Segment = std::array<double, 4>;

double distance_to_segment(double px, double py, const Segment& s)
{
    const double dx = s[2] - s[0], dy = s[3] - s[1];
    const double len2 = dx * dx + dy * dy;
    double u = len2 > 0 ? ((px - s[0]) * dx + (py - s[1]) * dy) / len2 : 0.0;
    u = std::clamp(u, 0.0, 1.0);
    return std::hypot(px - (s[0] + u * dx), py - (s[1] + u * dy));
}

void add_path(const std::vector<Coord>& path, bool closed, std::vector<Segment>& out)
{
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        out.push_back({path[i].x, path[i].y, path[i + 1].x, path[i + 1].y});
    }
    if (closed && path.size() > 1) {
        out.push_back({path.back().x, path.back().y, path.front().x, path.front().y});
    }
}

std::vector<Segment> boundary(const Geometry& g)
{
    std::vector<Segment> out;
    for (const Polygon& p : g.polygons) {
        for (const auto& ring : p.rings) add_path(ring, true, out);
    }
    for (const auto& line : g.lines) add_path(line, false, out);
    return out;
}

/// The largest distance of an output vertex from the input boundary.
double farthest_vertex(const Geometry& in, const Geometry& out)
{
    const std::vector<Segment> edges = boundary(in);
    double worst = 0.0;
    for (const Segment& s : boundary(out)) {
        double nearest = std::numeric_limits<double>::infinity();
        for (const Segment& e : edges) nearest = std::min(nearest, distance_to_segment(s[0], s[1], e));
        worst = std::max(worst, nearest);
    }
    return worst;
}

/// Checks the bound on every written feature; returns how many moved by more than t/10.
std::size_t expect_bound_holds(const std::vector<Feature>& in, const SnapResult& result, double t)
{
    std::size_t moved = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
        const FeatureOutput& out = result.features[i];
        if (out.geometry.empty()) continue;
        const double farthest = farthest_vertex(in[i].geometry, out.geometry);
        EXPECT_GE(out.max_displacement, farthest - 1e-9 * t) << "feature " << out.id;
        EXPECT_LE(out.max_displacement, 2 * t) << "feature " << out.id;
        moved += farthest > 0.1 * t;
    }
    return moved;
}

TEST(Displacement, ACornerMeetingANeighboursEdgeCountsTheMove)
{
    // B's lower-left corner is 0.3 above A's top edge (t = 1): the corner and the edge meet, and
    // whichever of the two moves carries a displacement of about 0.3 (here the corner moves onto
    // the edge, so B's input-vertex move bounds it, not A's edge deviation).
    const std::vector<Feature> in = {square(1, 0, 0, 10), square(2, 4, 10.3, 2)};
    const SnapResult result = snap(in, options_at(1.0));
    ASSERT_GT(result.stats.merges + result.stats.splits, 0u);
    EXPECT_GE(std::max(result.features[0].max_displacement, result.features[1].max_displacement), 0.29);
    EXPECT_EQ(expect_bound_holds(in, result, 1.0), 1u);
}

TEST(Displacement, BoundsEveryOutputVertexOnNearDegeneratePolygons)
{
    const double t = 1.0;
    const std::vector<Feature> in = near_degenerate_polygons(150, 200.0, t, 7);
    const SnapResult result = snap(in, options_at(t));
    EXPECT_GT(expect_bound_holds(in, result, t), 20u); // the case has to move vertices to test anything
}

TEST(Displacement, BoundsEveryOutputVertexOnAWiggledCoverage)
{
    const double t = 1.0;
    const std::vector<Feature> in = perturbed_grid_coverage(8, 8, 10.0, 0.2, 3, 6, 0.02);
    const SnapResult result = snap(in, options_at(t));
    EXPECT_GT(expect_bound_holds(in, result, t), 5u);
}

} // namespace
} // namespace trisnap

namespace trisnap {
namespace {

// snap(std::vector<Feature>&&) frees the input once the engine has its cleaned copy (the tiles do
// this when there is no cascade test): the same result, and the input is gone.
TEST(SnapOwningItsInput, GivesTheSameResultAndReleasesTheInput)
{
    const double t = 1.0;
    const std::vector<Feature> in = near_degenerate_polygons(60, 100.0, t, 11);
    const SnapResult kept = snap(in, options_at(t));
    std::vector<Feature> given = in;
    const SnapResult released = snap(std::move(given), options_at(t));
    EXPECT_TRUE(given.empty());        // NOLINT(bugprone-use-after-move): the overload empties it
    EXPECT_EQ(given.capacity(), 0u);   // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(output_by_id(released), output_by_id(kept));
    EXPECT_EQ(problem_lines(released.problems), problem_lines(kept.problems));
    EXPECT_EQ(released.stats.merges, kept.stats.merges);
    EXPECT_GT(kept.stats.merges + kept.stats.splits, 0u);
}

} // namespace
} // namespace trisnap
