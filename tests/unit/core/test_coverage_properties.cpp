// Perturbed grids of quadrilaterals forming a coverage (planar partition with exactly shared
// edges), 10^2..10^5 vertices, at tolerances from well below to above the edge wiggle: the
// contract on every output, and the coverage stays a coverage (no new overlap, no shared
// boundary lost). The 10^5 case carries the `slow` label (suite name contains "Slow").
#include "snap_harness.hpp"

#include "generators.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace trisnap {
namespace {

struct CoverageCase {
    std::string name;
    int n;                ///< n x n cells
    int points_per_edge;
    double tolerance;     ///< cells are 10 units wide
    double wiggle = 0.002;
    std::uint64_t seed = 1;
    /// Features the engine may flag (209 at corners where jitter brings three vertices within t),
    /// as measured when the bound was introduced: more means the engine got worse here.
    std::size_t max_flagged = 0;
};

std::ostream& operator<<(std::ostream& os, const CoverageCase& c) {
    return os << c.n << "x" << c.n << " ppe=" << c.points_per_edge << " t=" << c.tolerance
              << " wiggle=" << c.wiggle << " seed=" << c.seed;
}

void run_coverage(const CoverageCase& c) {
    const std::vector<Feature> in =
        perturbed_grid_coverage(c.n, c.n, 10.0, 0.2, c.seed, c.points_per_edge, c.wiggle);
    const CheckedRun run = snap_and_check(in, options_at(c.tolerance), c.max_flagged);
    std::cout << figures_line(c.name + " (" + std::to_string(vertex_count(in)) + " vertices)", run,
                              c.tolerance) << "\n";
    EXPECT_TRUE(contract_holds(run.report, c.tolerance)) << c;
    EXPECT_EQ(run.report.n_overlaps_new, 0u) << c;
    EXPECT_EQ(run.report.n_shared_lost, 0u) << c;
    // Cells are at least ~6 units wide: at t <= 1 no cell, part or hole may vanish. (Corners
    // where jitter brings three vertices within t of each other may report 209: allowed.)
    if (c.tolerance <= 1.0) {
        EXPECT_EQ(run.report.n_out, in.size()) << c;
        for (ProblemCode code : {ProblemCode::collapsed_polygon, ProblemCode::part_removed,
                                 ProblemCode::hole_removed, ProblemCode::topology_changed})
            EXPECT_EQ(count_code(run.result, code), 0u) << c << " code " << static_cast<int>(code);
    }
}

class Coverage : public ::testing::TestWithParam<CoverageCase> {};
class CoverageSlow : public ::testing::TestWithParam<CoverageCase> {};

TEST_P(Coverage, ContractHoldsAndCoverageStaysACoverage) { run_coverage(GetParam()); }
TEST_P(CoverageSlow, ContractHoldsAndCoverageStaysACoverage) { run_coverage(GetParam()); }

std::string case_name(const ::testing::TestParamInfo<CoverageCase>& info) { return info.param.name; }

// Vertex counts are about n*n*(5 + 4*ppe): 4x5 -> 10^2, 10x10 ppe1 -> 10^3,
// 24x24 ppe3 -> 10^4, 77x77 ppe3 -> 10^5.
INSTANTIATE_TEST_SUITE_P(Sizes, Coverage, ::testing::Values(
    CoverageCase{"v1e2_t0_01", 5, 0, 0.01},
    CoverageCase{"v1e2_t1", 5, 0, 1.0},
    CoverageCase{"v1e3_t0_001", 10, 1, 0.001},
    CoverageCase{"v1e3_t0_01", 10, 1, 0.01},
    CoverageCase{"v1e3_t0_1", 10, 1, 0.1},
    CoverageCase{"v1e3_t1", 10, 1, 1.0},
    CoverageCase{"v1e3_t3", 10, 1, 3.0},
    CoverageCase{"v1e3_t0_05_wiggly", 10, 4, 0.05, 0.01, 2},
    CoverageCase{"v1e4_t0_01", 24, 3, 0.01},
    CoverageCase{"v1e4_t0_3", 24, 3, 0.3, 0.02, 3},
    CoverageCase{"v1e4_t2", 24, 3, 2.0, 0.002, 4, 2}), case_name);

INSTANTIATE_TEST_SUITE_P(Sizes, CoverageSlow, ::testing::Values(
    CoverageCase{"v1e5_t0_05", 77, 3, 0.05, 0.01, 5, 0},
    CoverageCase{"v1e5_t1", 77, 3, 1.0, 0.01, 6, 2}), case_name);

} // namespace
} // namespace trisnap
