// The output depends on the features, not on their order or on how often we snap:
//  - any permutation of the input gives the same geometry per id and the same problems;
//  - snapping an output again at the same t moves nothing.
#include "snap_harness.hpp"

#include "core/wkt.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace trisnap {
namespace {

/// Fisher-Yates with our own integer mapping, so the order is the same with any std library.
std::vector<Feature> shuffled(std::vector<Feature> features, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    for (std::size_t i = features.size(); i > 1; --i)
        std::swap(features[i - 1], features[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<std::int64_t>(i) - 1))]);
    return features;
}

/// The first id whose output differs between a and b, with both WKTs; "" when none does.
std::string first_difference(const SnapResult& a, const SnapResult& b) {
    const auto wa = output_by_id(a), wb = output_by_id(b);
    if (wa.size() != wb.size())
        return "different id sets";
    for (const auto& [id, wkt] : wa) {
        auto it = wb.find(id);
        if (it == wb.end())
            return "id " + std::to_string(id) + " missing";
        if (it->second != wkt)
            return "id " + std::to_string(id) + ":\n  " + wkt + "\n  " + it->second;
    }
    return {};
}

void expect_order_free(const std::vector<Feature>& in, double t) {
    const SnapResult reference = snap(in, options_at(t));
    const std::vector<Feature> reversed(in.rbegin(), in.rend());
    std::vector<std::vector<Feature>> orders = {reversed};
    for (std::uint64_t seed : {1u, 2u, 3u})
        orders.push_back(shuffled(in, seed));
    for (std::size_t k = 0; k < orders.size(); ++k) {
        const SnapResult other = snap(orders[k], options_at(t));
        EXPECT_EQ(first_difference(reference, other), "") << "order " << k << " t=" << t;
        EXPECT_EQ(problem_lines(reference.problems), problem_lines(other.problems)) << "order " << k;
    }
}

TEST(Permutation, CoverageGivesTheSameOutputInAnyOrder) {
    for (double t : {0.05, 1.0, 3.0})
        expect_order_free(perturbed_grid_coverage(10, 10, 10.0, 0.2, 31, 2, 0.01), t);
}

TEST(Permutation, NearDegeneratePolygonsGiveTheSameOutputInAnyOrder) {
    for (std::uint64_t seed : {1u, 2u, 3u})
        expect_order_free(near_degenerate_polygons(120, 150.0, 1.0, seed), 1.0);
}

TEST(Permutation, VertexClusterGivesTheSameOutputInAnyOrder) {
    expect_order_free(vertex_cluster(9, 1.0, 5), 1.0);
}

TEST(Permutation, MixedLinesAndPolygonsGiveTheSameOutputInAnyOrder) {
    std::vector<Feature> in = near_degenerate_polygons(60, 80.0, 1.0, 41);
    for (int i = 0; i < 10; ++i) {
        Feature line = dense_line(1000 + i, 60, 1.7, 0.5, 50 + i);
        for (Coord& c : line.geometry.lines[0])
            c.y += 10.0 * i;
        in.push_back(line);
    }
    expect_order_free(in, 1.0);
}

void expect_idempotent(const std::vector<Feature>& in, double t) {
    const SnapResult once = snap(in, options_at(t));
    const SnapResult twice = snap(output_as_input(once), options_at(t));
    std::size_t changed = 0;
    std::string example;
    const auto a = output_by_id(once), b = output_by_id(twice);
    for (const auto& [id, wkt] : b) {
        if (a.at(id) == wkt)
            continue;
        if (changed++ == 0)
            example = "id " + std::to_string(id) + ":\n  once  " + a.at(id) + "\n  twice " + wkt;
    }
    EXPECT_EQ(changed, 0u) << "t=" << t << ", first change: " << example;
    EXPECT_EQ(problem_lines(twice.problems), "") << "t=" << t;
}

TEST(Idempotence, SnappingACoverageOutputAgainMovesNothing) {
    for (double t : {0.05, 1.0, 3.0})
        expect_idempotent(perturbed_grid_coverage(10, 10, 10.0, 0.2, 32, 2, 0.01), t);
}

TEST(Idempotence, SnappingANearDegenerateOutputAgainMovesNothing) {
    for (std::uint64_t seed : {1u, 2u, 3u})
        expect_idempotent(near_degenerate_polygons(200, 200.0, 1.0, seed), 1.0);
}

// Not tested with an output grid: there the engine snaps with margins (t + 2g) so that
// rounding cannot break the contract, and an output whose vertices are between t and t + 2g
// apart legitimately moves again.

TEST(Determinism, SameInputTwiceGivesIdenticalOutput) {
    const std::vector<Feature> in = near_degenerate_polygons(300, 250.0, 1.0, 77);
    const SnapResult a = snap(in, options_at(1.0));
    const SnapResult b = snap(in, options_at(1.0));
    EXPECT_EQ(first_difference(a, b), "");
    EXPECT_EQ(problem_lines(a.problems), problem_lines(b.problems));
}

} // namespace
} // namespace trisnap
