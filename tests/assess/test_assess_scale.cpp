// Scale smoke: a 316 x 316 grid of unit squares (99,856 polygons) against a copy with three known
// defects. No timing assertion (speed lives in benchmarks); the counts must be exact.
#include "assess_fixture.hpp"

#include <gtest/gtest.h>

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

} // namespace
} // namespace trisnap::test
