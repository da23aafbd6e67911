// Scale smoke: a 316 x 316 grid of unit squares (99,856 polygons) against a copy with three known
// defects, and 10,000 stacked copies of one square against Andorra (5·10^7 overlapping pairs).
// The counts must be exact; the only time bound is a CPU bound 30x above what it takes, there
// to catch a return of the per-pair (quadratic) overlap test.
#include "assess_fixture.hpp"
#include "test_data.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <ctime>

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

TEST(AssessScale, TenThousandStackedSquaresAgainstAndorra)
{
    const auto path = shared_data("snapoly_andorra/andorra.gpkg");
    if (!path) {
        GTEST_SKIP() << "../shared/data/snapoly_andorra/andorra.gpkg is absent";
    }
    GDALAllRegister();
    GDALDatasetUniquePtr andorra(GDALDataset::Open(path->c_str(), GDAL_OF_VECTOR));
    ASSERT_TRUE(andorra);
    constexpr std::int64_t n = 10000;
    std::vector<Item> stacked;
    for (std::int64_t fid = 1; fid <= n; ++fid) {
        stacked.push_back({fid, "POLYGON((1.5 42.5,1.51 42.5,1.51 42.51,1.5 42.51,1.5 42.5))"});
    }
    GDALDatasetUniquePtr squares = make_layer(stacked);
    const LayerSource in{*andorra, *andorra->GetLayer(0)};
    const AssessReport input = assess_layers(in, in, AssessOptions{1e-6, "", 20});
    const std::clock_t start = std::clock();
    const AssessReport r = assess_layers(in, {*squares, *squares->GetLayer(0)}, AssessOptions{1e-6, "", 20});
    const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    EXPECT_EQ(r.n_overlaps, n * (n - 1) / 2);
    EXPECT_NEAR(r.overlap_area, static_cast<double>(n * (n - 1) / 2) * 1e-4, 1e-6);
    EXPECT_GT(input.n_overlaps, 0) << "Andorra's landuse overlaps itself";
    EXPECT_EQ(r.n_overlaps_new, r.n_overlaps - input.n_overlaps)
        << "every pair of Andorra features that overlapped has stacked outputs that overlap: not new";
    EXPECT_EQ(r.overlaps.size(), 20u);
    EXPECT_EQ(r.overlaps.back().fid_a, 1) << "the 20 first pairs by FID among the new ones";
    EXPECT_LT(cpu, 30.0) << "one exact test per pair took > 1000 s of CPU here";
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
