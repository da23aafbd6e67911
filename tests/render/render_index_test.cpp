// The render grid index against brute force: visit(p, r) must reach every segment or point
// within r of p, on random layers and adversarial ones (items on cell boundaries, horizontal
// and vertical segments, huge and tiny coordinates, cells tiny against the coordinates).
#include "render/grid_index.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace trisnap::render {
namespace {

/// Items within r of p (slightly inside, so rounding in the reference distance cannot demand
/// an item the index may rightly leave out) that visit() did not reach.
std::size_t missed_segments(const GridIndex& index, const std::vector<Segment>& segments, XY p, double r)
{
    std::set<std::uint32_t> seen;
    index.visit(p, r, [&](std::uint32_t i) { seen.insert(i); });
    std::size_t missed = 0;
    for (std::uint32_t i = 0; i < segments.size(); ++i) {
        if (distance_to_segment(p, segments[i].a, segments[i].b) <= r * (1 - 1e-12) && !seen.count(i)) {
            ++missed;
        }
    }
    return missed;
}

std::vector<Segment> random_segments(std::mt19937_64& rng, std::size_t n, double scale, XY offset)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0), len(0.0, 0.2);
    std::vector<Segment> out;
    for (std::size_t i = 0; i < n; ++i) {
        const XY a{offset.x + scale * u(rng), offset.y + scale * u(rng)};
        XY b{a.x + scale * len(rng) * u(rng), a.y + scale * len(rng) * u(rng)};
        if (i % 5 == 1) {
            b.y = a.y; // horizontal
        } else if (i % 5 == 2) {
            b.x = a.x; // vertical
        } else if (i % 5 == 3) {
            b = a; // a point
        }
        out.push_back({a, b});
    }
    return out;
}

void expect_segments_found(const std::vector<Segment>& segments, double cell, double scale, XY offset,
                           std::mt19937_64& rng)
{
    const GridIndex index(segments, cell);
    std::uniform_real_distribution<double> u(-1.1, 1.1), radius(0.0, 0.1);
    std::size_t missed = 0;
    for (int k = 0; k < 300; ++k) {
        const XY p{offset.x + scale * u(rng), offset.y + scale * u(rng)};
        missed += missed_segments(index, segments, p, scale * radius(rng));
    }
    EXPECT_EQ(missed, 0u);
}

TEST(RenderGridIndex, SegmentsWithinRadiusAreVisited)
{
    std::mt19937_64 rng(31);
    for (double scale : {1.0, 1e-6, 1e-150, 1e6, 1e150}) {
        for (XY offset : {XY{0, 0}, XY{4.35 * scale, 52.0 * scale}}) {
            const auto segments = random_segments(rng, 500, scale, offset);
            for (double cell : {0.001 * scale, 0.05 * scale, GridIndex::cell_for(segments, 0.01 * scale)}) {
                SCOPED_TRACE("scale " + std::to_string(scale) + " cell " + std::to_string(cell / scale));
                expect_segments_found(segments, cell, scale, offset, rng);
            }
        }
    }
}

TEST(RenderGridIndex, SegmentsOnCellBoundaries)
{
    // Endpoints and whole segments exactly on the lines x = k*cell and y = k*cell.
    const double cell = 0.25;
    std::vector<Segment> segments;
    for (int i = -8; i <= 8; ++i) {
        segments.push_back({{i * cell, -2.0}, {i * cell, 2.0}});
        segments.push_back({{-2.0, i * cell}, {2.0, i * cell}});
        segments.push_back({{i * cell, i * cell}, {(i + 1) * cell, (i + 2) * cell}});
        segments.push_back({{i * cell, 0.0}, {i * cell, 0.0}});
    }
    const GridIndex index(segments, cell);
    std::size_t missed = 0;
    for (int i = -9; i <= 9; ++i) {
        for (int j = -9; j <= 9; ++j) {
            for (double r : {0.0, 1e-12, 0.1, 0.25}) {
                missed += missed_segments(index, segments, XY{i * cell + 0.125 * (j % 2), j * cell}, r);
            }
        }
    }
    EXPECT_EQ(missed, 0u);
}

TEST(RenderGridIndex, PointsWithinRadiusAreVisited)
{
    std::mt19937_64 rng(32);
    std::uniform_real_distribution<double> u(-1.0, 1.0), radius(0.0, 0.05);
    for (double scale : {1.0, 1e-150, 1e150}) {
        std::vector<XY> points;
        for (int i = 0; i < 2000; ++i) {
            points.push_back({scale * u(rng), scale * u(rng)});
        }
        const GridIndex index(points, 0.01 * scale);
        std::size_t missed = 0;
        for (int k = 0; k < 300; ++k) {
            const XY p{scale * u(rng), scale * u(rng)};
            const double r = scale * radius(rng);
            std::set<std::uint32_t> seen;
            index.visit(p, r, [&](std::uint32_t i) { seen.insert(i); });
            for (std::uint32_t i = 0; i < points.size(); ++i) {
                missed += distance(p, points[i]) <= r * (1 - 1e-12) && !seen.count(i) ? 1 : 0;
            }
        }
        EXPECT_EQ(missed, 0u) << "scale " << scale;
    }
}

TEST(RenderGridIndex, FarCoordinatesAtATinyCellStayBounded)
{
    // Cells of 1e-9 against coordinates of 1e12 and more: cell numbers are clamped, items share
    // the edge cells, and every item within r is still visited.
    std::vector<XY> points{{1e12, 1e12}, {-1e300, 5.0}, {1e300, -1e300}, {0.0, 0.0}, {3e-9, 0.0}};
    const GridIndex index(points, 1e-9);
    for (const XY& p : points) {
        std::set<std::uint32_t> seen;
        index.visit(p, 1e-9, [&](std::uint32_t i) { seen.insert(i); });
        for (std::uint32_t i = 0; i < points.size(); ++i) {
            if (distance(p, points[i]) <= 1e-9) {
                EXPECT_TRUE(seen.count(i)) << p.x << " " << p.y << " misses " << i;
            }
        }
    }
}

TEST(RenderGridIndex, SegmentSpanningAstronomicallyManyCellsIsStillFound)
{
    // A segment from -1e300 to 1e300 at a cell of 1e-9 spans ~1e309 cells (8e18 after
    // clamping): walking them never ended. It is now visited by every query.
    const std::vector<Segment> segments{{{-1e300, 0.0}, {1e300, 0.0}},
                                        {{0.0, -1e12}, {0.0, 1e12}},
                                        {{5.0, 5.0}, {5.0 + 1e-9, 5.0}}};
    const GridIndex index(segments, 1e-9);
    for (XY p : {XY{0.5, 1e-10}, XY{-3e299, 0.0}, XY{5.0, 5.0}, XY{1e-10, 7.0}}) {
        EXPECT_EQ(missed_segments(index, segments, p, 1e-9), 0u) << p.x << " " << p.y;
    }
}

} // namespace
} // namespace trisnap::render
