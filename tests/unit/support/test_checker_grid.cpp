// The contract checker's own segment grid against brute force: visit_near(x, y, r) must reach
// every segment within r, and nearest_in_range must find the nearest, on random segments and
// adversarial ones (cell boundaries, zero-length segments, huge and tiny coordinates, one
// enormous segment among short ones).
#include "checker_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace trisnap::checker_detail {
namespace {

std::vector<Segment> random_segments(std::mt19937_64& rng, std::size_t n, double scale, double ox, double oy)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0), len(0.0, 0.1);
    std::vector<Segment> out;
    for (std::size_t i = 0; i < n; ++i) {
        const double ax = ox + scale * u(rng), ay = oy + scale * u(rng);
        double bx = ax + scale * len(rng) * u(rng), by = ay + scale * len(rng) * u(rng);
        if (i % 4 == 1) {
            bx = ax; // vertical, or a point when by == ay too
        } else if (i % 4 == 2) {
            by = ay;
        }
        out.push_back({ax, ay, bx, by, static_cast<std::uint32_t>(i)});
    }
    return out;
}

/// Segments within r of (x, y) that visit_near did not report, plus whether nearest_in_range
/// disagreed with the brute-force nearest distance.
std::size_t misses(const SegmentGrid& grid, const std::vector<Segment>& segments, double x, double y, double r)
{
    std::set<std::uint32_t> seen;
    grid.visit_near(x, y, r, [&](std::uint32_t i) { seen.insert(i); });
    std::size_t missed = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t i = 0; i < segments.size(); ++i) {
        const double d = point_segment_distance(x, y, segments[i]);
        best = std::min(best, d);
        if (d <= r * (1 - 1e-12) && !seen.count(i)) {
            ++missed;
        }
    }
    const Nearest nearest = grid.nearest_in_range(x, y, 0, segments.size(), r > 0 ? r : 1.0);
    if (nearest.distance != best) {
        ADD_FAILURE() << "nearest at " << x << " " << y << ": " << nearest.distance << ", brute force " << best;
    }
    return missed;
}

TEST(CheckerSegmentGrid, VisitAndNearestMatchBruteForce)
{
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<double> u(-1.2, 1.2), radius(0.0, 0.1);
    for (double scale : {1.0, 1e-7, 1e-150, 1e7, 1e150}) {
        for (double min_cell : {0.001, 0.02, 0.3}) {
            const double ox = 4.35 * scale, oy = 52.0 * scale;
            const auto segments = random_segments(rng, 800, scale, ox, oy);
            const SegmentGrid grid(segments, min_cell * scale);
            std::size_t missed = 0;
            for (int k = 0; k < 200; ++k) {
                missed += misses(grid, segments, ox + scale * u(rng), oy + scale * u(rng), scale * radius(rng));
            }
            EXPECT_EQ(missed, 0u) << "scale " << scale << " min cell " << min_cell;
        }
    }
}

TEST(CheckerSegmentGrid, SegmentsOnCellBoundariesAndOneHugeSegment)
{
    std::vector<Segment> segments;
    for (int i = -6; i <= 6; ++i) {
        const double v = i * 0.5;
        segments.push_back({v, -3.0, v, 3.0, 0});
        segments.push_back({-3.0, v, 3.0, v, 0});
        segments.push_back({v, v, v, v, 0});
    }
    segments.push_back({-1e6, -1e6, 1e6, 1e6 + 1.0, 0}); // the piece budget coarsens the cells
    const SegmentGrid grid(segments, 0.5);
    std::size_t missed = 0;
    for (int i = -7; i <= 7; ++i) {
        for (int j = -7; j <= 7; ++j) {
            for (double r : {0.0, 0.25, 0.5, 1.0}) {
                missed += misses(grid, segments, i * 0.5, j * 0.25, r);
            }
        }
    }
    EXPECT_EQ(missed, 0u);
}

TEST(CheckerSegmentGrid, ExtentBeyondTheDoubleRange)
{
    // Coordinates at +-1e308 and +-1.7e308: the extents (2e308, 3.4e308) overflow to infinity,
    // the segments themselves are short enough to measure.
    const std::vector<Segment> segments{{-1e308, 0.0, -1e308, 1.0, 0},
                                        {1e308, 0.0, 1e308, 1.0, 1},
                                        {0.0, -1.7e308, 0.0, -1.6e308, 2},
                                        {0.0, 1.7e308, 1.0, 1.7e308, 3},
                                        {0.0, 0.0, 1.0, 0.0, 4}};
    const SegmentGrid grid(segments, 1.0);
    std::size_t missed = 0;
    for (const Segment& s : segments) {
        missed += misses(grid, segments, s.ax, s.ay, 1.0);
    }
    EXPECT_EQ(missed, 0u);
}

TEST(CheckerSegmentGrid, HugeCoordinatesAtATinyCell)
{
    // Found by fuzz_snap: y = 4.8e301 with x and the cell near 1e-113, so y / cell overflowed
    // (NaN cell numbers, undefined behaviour under UBSan).
    const std::vector<Segment> segments{{1.386e-113, 4.844e301, -1.7e-113, 4.844e301, 0},
                                        {-1.7e-113, 4.844e301, 1.8e-307, 4.844e301, 1},
                                        {1e-113, 4.844e301, 1e-113, 4.844e301, 2}};
    const SegmentGrid grid(segments, 0x1p-383);
    std::size_t missed = 0;
    for (const Segment& s : segments) {
        missed += misses(grid, segments, s.ax, s.ay, 1e-113);
    }
    EXPECT_EQ(missed, 0u);
}

} // namespace
} // namespace trisnap::checker_detail
