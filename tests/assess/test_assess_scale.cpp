// Scale smoke: a 316 x 316 grid of unit squares (99,856 polygons) against a copy with three known
// defects. No timing assertion (speed lives in benchmarks); the counts must be exact.
#include "assess_fixture.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

namespace trisnap::test {
namespace {

TEST(AssessScale, HundredThousandPolygonGrid)
{
    constexpr int n = 316;
    std::vector<Item> in, out;
    in.reserve(n * n);
    out.reserve(n * n);
    const std::int64_t removed = 10 * n + 10 + 1, shifted = 200 * n + 200 + 1;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const std::int64_t fid = row * n + col + 1;
            in.push_back({fid, square(col, row, 1)});
            if (fid == removed) continue;
            out.push_back({fid, square(col + (fid == shifted ? 0.5 : 0.0), row, 1)});
        }
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_in, n * n);
    EXPECT_EQ(r.n_out, n * n - 1);
    EXPECT_EQ(r.n_missing, 1);
    EXPECT_EQ(r.missing.at(0).fid_a, removed);
    EXPECT_EQ(r.n_extra, 0);
    EXPECT_EQ(r.n_invalid, 0);
    EXPECT_EQ(r.n_shared_in, 2 * n * (n - 1));
    EXPECT_EQ(r.n_overlaps, 1); // the shifted square over its right neighbour
    EXPECT_NEAR(r.overlap_area, 0.5, 1e-9);
    EXPECT_EQ(r.gaps_new, 1); // ...and away from its left neighbour
    EXPECT_EQ(r.gaps_new_examples.at(0).fid_b, shifted);
    EXPECT_NEAR(r.max_hausdorff, 0.5, 1e-4);
    EXPECT_EQ(r.p99_hausdorff, 0.0);
    EXPECT_DOUBLE_EQ(*r.min_vertex_vertex, 0.5);
    EXPECT_GT(r.n_crossings, 0); // collinear overlaps along the shifted square's top and bottom
    EXPECT_NEAR(r.area_change, -1.0 / (n * n), 1e-12);
}

/// A jittered grid: interior corners moved by up to 0.3, so boxes of neighbours overlap.
std::vector<Item> jittered_grid(int n, std::uint32_t seed)
{
    std::vector<double> dx((n + 1) * (n + 1)), dy((n + 1) * (n + 1));
    for (std::size_t i = 0; i < dx.size(); ++i) {
        seed = seed * 1664525u + 1013904223u;
        dx[i] = ((seed >> 8) % 1000) / 1000.0 * 0.6 - 0.3;
        seed = seed * 1664525u + 1013904223u;
        dy[i] = ((seed >> 8) % 1000) / 1000.0 * 0.6 - 0.3;
    }
    const auto corner = [&](int i, int j) {
        const bool edge = i == 0 || j == 0 || i == n || j == n;
        const std::size_t k = static_cast<std::size_t>(j * (n + 1) + i);
        return fmt::format("{} {}", i + (edge ? 0 : dx[k]), j + (edge ? 0 : dy[k]));
    };
    std::vector<Item> items;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            items.push_back({j * n + i + 1, fmt::format("POLYGON(({},{},{},{},{}))", corner(i, j), corner(i + 1, j),
                                                        corner(i + 1, j + 1), corner(i, j + 1), corner(i, j))});
    return items;
}

TEST(AssessScale, SameReportOnOneThreadAndMany)
{
    // Every third output feature comes from a grid jittered otherwise: overlaps, crossings, gaps.
    const std::vector<Item> in = jittered_grid(60, 1), other = jittered_grid(60, 2);
    std::vector<Item> out = in;
    for (std::size_t i = 0; i < out.size(); i += 3) out[i] = other[i];
    const auto report = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        nlohmann::json j = nlohmann::json::parse(assess_report_json(assess_items(in, out, 0.05)));
        j.erase("seconds");
        j.erase("timings");
        return j;
    };
    const nlohmann::json one = report(1), many = report(4);
    EXPECT_GT(one["n_overlaps"].get<int>(), 0);
    EXPECT_GT(one["n_crossings"].get<int>(), 0);
    EXPECT_GT(one["gaps_new"].get<int>(), 0);
    EXPECT_EQ(one.dump(), many.dump());
}

} // namespace
} // namespace trisnap::test
