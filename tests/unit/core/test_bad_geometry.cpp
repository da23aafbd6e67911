// Bad input geometry is reported, never thrown: one problem code per kind of defect, the
// feature repaired when it can be, and the contract on what comes out.
#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace trisnap {
namespace {

constexpr double t = 1.0;

Feature feature(std::int64_t id, const std::string& wkt) { return {id, read_wkt(wkt)}; }

/// The feature under test (id 1) beside a healthy square (id 2), which must come out unchanged;
/// `max_flagged`: 1 when the feature under test is repaired (105), else 0.
CheckedRun run_beside_square(const std::string& wkt, std::size_t max_flagged = 0) {
    return snap_and_check({feature(1, wkt), feature(2, "POLYGON ((20 0, 30 0, 30 10, 20 10, 20 0))")},
                          options_at(t), max_flagged);
}

void expect_square_untouched(const CheckedRun& run) {
    ASSERT_EQ(run.result.features.size(), 2u);
    EXPECT_EQ(to_wkt(run.result.features[1].geometry), "POLYGON ((20 0, 30 0, 30 10, 20 10, 20 0))");
}

TEST(BadGeometry, NanCoordinateRejectsTheFeatureWith106) {
    Feature f = feature(1, "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))");
    f.geometry.polygons[0].rings[0][2].x = std::numeric_limits<double>::quiet_NaN();
    const CheckedRun run = snap_and_check({f, feature(2, "POLYGON ((20 0, 30 0, 30 10, 20 10, 20 0))")}, options_at(t), 0);
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::non_finite_coordinate)) << problem_lines(run.result.problems);
    EXPECT_TRUE(run.result.features[0].geometry.empty());
    expect_square_untouched(run);
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, InfiniteCoordinateOnALineRejectsTheFeatureWith106) {
    Feature f = feature(1, "LINESTRING (0 0, 10 0, 10 10)");
    f.geometry.lines[0][1].y = std::numeric_limits<double>::infinity();
    const SnapResult r = snap({f}, options_at(t));
    EXPECT_TRUE(has_problem(r, 1, ProblemCode::non_finite_coordinate)) << problem_lines(r.problems);
}

TEST(BadGeometry, EmptyGeometryIsReportedWith107) {
    for (const char* wkt : {"POLYGON EMPTY", "MULTIPOLYGON EMPTY", "LINESTRING EMPTY", "GEOMETRYCOLLECTION EMPTY"}) {
        const CheckedRun run = run_beside_square(wkt);
        EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::empty_geometry)) << wkt << ": " << problem_lines(run.result.problems);
        expect_square_untouched(run);
        EXPECT_TRUE(contract_holds(run.report, t)) << wkt;
    }
}

TEST(BadGeometry, UnclosedRingIsClosedAndReportedWith101) {
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 0, 10 10, 0 10))");
    EXPECT_EQ(problem_lines(run.result.problems), "1 101\n");
    EXPECT_EQ(to_wkt(run.result.features[0].geometry), "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))");
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, RepeatedPointsAreRemovedAndReportedWith102) {
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 0, 10 0, 10 10, 10 10, 0 10, 0 0))");
    EXPECT_EQ(problem_lines(run.result.problems), "1 102\n");
    EXPECT_EQ(to_wkt(run.result.features[0].geometry), "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))");
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, RingWithTwoDistinctPointsIsDroppedWith103) {
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 0, 0 0))");
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::degenerate_ring)) << problem_lines(run.result.problems);
    EXPECT_TRUE(run.result.features[0].geometry.empty());
    expect_square_untouched(run);
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, RingGoingBackAndForthBetweenTwoPointsIsDroppedWith103) {
    // Same two distinct points as above, written five times: still fewer than 3 distinct points.
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 0, 0 0, 10 0, 0 0))");
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::degenerate_ring)) << problem_lines(run.result.problems);
    EXPECT_TRUE(run.result.features[0].geometry.empty());
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, DegenerateHoleIsDroppedButTheShellKept) {
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (2 2, 5 2, 2 2))");
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::degenerate_ring)) << problem_lines(run.result.problems);
    EXPECT_EQ(to_wkt(run.result.features[0].geometry), "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))");
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, LineWithOneDistinctPointIsReportedWith104) {
    const CheckedRun run = run_beside_square("LINESTRING (3 3, 3 3)");
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::degenerate_line)) << problem_lines(run.result.problems);
    EXPECT_TRUE(run.result.features[0].geometry.empty());
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, SelfIntersectingRingIsRepairedWith105) {
    const CheckedRun run = run_beside_square("POLYGON ((0 0, 10 10, 10 0, 0 10, 0 0))", 1);
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::self_intersection)) << problem_lines(run.result.problems);
    EXPECT_EQ(run.result.features[0].geometry.polygons.size(), 2u);
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, OverlappingRingsOfOneFeatureAreRepairedWith105) {
    // Two shells of one multipolygon that overlap: the odd-even rule leaves the overlap out.
    const CheckedRun run = run_beside_square(
        "MULTIPOLYGON (((0 0, 6 0, 6 6, 0 6, 0 0)), ((3 3, 9 3, 9 9, 3 9, 3 3)))", 1);
    EXPECT_TRUE(has_problem(run.result, 1, ProblemCode::self_intersection)) << problem_lines(run.result.problems);
    EXPECT_TRUE(contract_holds(run.report, t));
}

TEST(BadGeometry, DuplicateFeatureIdsAreAllAnswered) {
    const CheckedRun run = snap_and_check({feature(7, "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))"),
                                           feature(7, "POLYGON ((20 0, 30 0, 30 10, 20 10, 20 0))")},
                                          options_at(t), 0);
    ASSERT_EQ(run.result.features.size(), 2u);
    EXPECT_FALSE(run.result.features[0].geometry.empty());
    EXPECT_FALSE(run.result.features[1].geometry.empty());
}

} // namespace
} // namespace trisnap
