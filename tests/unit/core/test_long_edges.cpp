// The long edges' grid (src/core/long_edges.hpp) against brute force: for points near random
// segments (every orientation, axis-parallel ones, lengths from one radius to hundreds, some
// with huge offsets), "is an edge within r of p?" answered through p's cell must equal the
// answer over every edge, before and after erasing (no erased edge still listed), and erasing
// everything must leave nothing.
// A point within r of an edge whose capsule was not put in the point's cell would make the
// engine's walk skip an edge that can give a split: the fix-point check of the engine tests
// would then see a missed event; this sees it directly.
#include "core/long_edges.hpp"
#include "core/mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace trisnap {
namespace {

using detail::LongEdgeIndex;

struct Segment {
    double ax, ay, bx, by;
};

double dist2(const Segment& s, double px, double py)
{
    return detail::squared_distance_point_segment(px, py, s.ax, s.ay, s.bx, s.by);
}

void expect_same_answers(const LongEdgeIndex& index, const std::vector<Segment>& segments,
                         const std::vector<bool>& present, double r, double ox, double oy, std::mt19937_64& rng)
{
    std::uniform_real_distribution<double> along(-0.2, 1.2);
    std::uniform_real_distribution<double> off(-1.5, 1.5);
    for (int probe = 0; probe < 4000; ++probe) {
        // Points near a random segment (most within a few r of it), and a few anywhere.
        const Segment& s = segments[rng() % segments.size()];
        const double u = along(rng);
        double px = s.ax + u * (s.bx - s.ax) + off(rng) * r;
        double py = s.ay + u * (s.by - s.ay) + off(rng) * r;
        if (probe % 10 == 0) {
            px = ox + std::uniform_real_distribution<double>(-50, 150)(rng) * r;
            py = oy + std::uniform_real_distribution<double>(-50, 150)(rng) * r;
        }
        bool brute = false;
        for (std::size_t i = 0; i < segments.size(); ++i) {
            brute = brute || (present[i] && dist2(segments[i], px, py) <= r * r);
        }
        bool indexed = false;
        ASSERT_TRUE(index.each(px, py, [&](std::uint64_t key) {
            ASSERT_TRUE(present[key]) << "an erased edge is still listed";
            indexed = indexed || dist2(segments[key], px, py) <= r * r;
        }));
        ASSERT_EQ(indexed, brute) << "point " << px << " " << py;
    }
}

void run_case(double r, double ox, double oy, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coord(0, 100);
    std::uniform_real_distribution<double> length(1, 120);
    std::uniform_real_distribution<double> angle(0, 6.283185307179586);
    std::vector<Segment> segments;
    for (int i = 0; i < 300; ++i) {
        const double ax = ox + coord(rng) * r, ay = oy + coord(rng) * r;
        const double len = length(rng) * r;
        double a = angle(rng);
        if (i % 7 == 0) a = (i % 4) * 1.5707963267948966; // axis-parallel, vertical included
        segments.push_back({ax, ay, ax + len * std::cos(a), ay + len * std::sin(a)});
    }
    LongEdgeIndex index;
    index.reset(r * r);
    std::vector<bool> present(segments.size(), false);
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const Segment& s = segments[i];
        ASSERT_TRUE(index.insert(s.ax, s.ay, s.bx, s.by, i));
        present[i] = true;
    }
    expect_same_answers(index, segments, present, r, ox, oy, rng);
    for (std::size_t i = 0; i < segments.size(); i += 2) {
        const Segment& s = segments[i];
        ASSERT_TRUE(index.erase(s.ax, s.ay, s.bx, s.by, i));
        present[i] = false;
    }
    expect_same_answers(index, segments, present, r, ox, oy, rng);
    for (std::size_t i = 1; i < segments.size(); i += 2) {
        const Segment& s = segments[i];
        ASSERT_TRUE(index.erase(s.ax, s.ay, s.bx, s.by, i));
    }
    EXPECT_EQ(index.entries(), 0u);
}

TEST(LongEdgeIndex, AnswersAsBruteForceDoes)
{
    run_case(1.0, 0.0, 0.0, 1);
    run_case(0.005, -75.6, 38.8, 2);  // degrees at NJ shore's tolerance
    run_case(1e-7, 1e6, -2e6, 3);     // a small radius far from the origin
}

TEST(LongEdgeIndex, RefusesWhatItCannotHold)
{
    LongEdgeIndex index;
    index.reset(1.0);
    // More cells than max_cells: a diagonal much longer than the radius.
    EXPECT_FALSE(index.insert(0, 0, 1e5, 1e5, 1));
    EXPECT_FALSE(index.erase(0, 0, 1e5, 1e5, 1));
    // Beyond the grid's exact range.
    EXPECT_FALSE(index.insert(1e300, 0, 1e300 + 1e290, 0, 2));
    EXPECT_EQ(index.entries(), 0u);
    // A point beyond the range: the caller must look at every edge.
    int calls = 0;
    EXPECT_FALSE(index.each(1e300, 0, [&](std::uint64_t) { ++calls; }));
    EXPECT_TRUE(index.each(5, 5, [&](std::uint64_t) { ++calls; }));
    EXPECT_EQ(calls, 0) << "an empty index lists nothing";
}

} // namespace
} // namespace trisnap
