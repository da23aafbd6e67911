// Options are validated before any geometry is touched: a bad value throws
// std::invalid_argument whose message names the option.
#include "snap_harness.hpp"

#include "core/snap.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace trisnap {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

/// The message snap() throws for `options`, or "" when it does not throw.
std::string rejection(const SnapOptions& options) {
    try {
        snap({square(1, 0, 0, 10)}, options);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return {};
}

SnapOptions with_tolerance(double t) {
    SnapOptions o;
    o.tolerance = t;
    return o;
}

TEST(Options, ToleranceMustBeFiniteAndPositive) {
    for (double t : {0.0, -1.0, -0.0, nan, inf, -inf}) {
        const std::string msg = rejection(with_tolerance(t));
        EXPECT_NE(msg.find("tolerance"), std::string::npos) << "t=" << t << ": '" << msg << "'";
        EXPECT_FALSE(validate(with_tolerance(t)).empty()) << "t=" << t;
    }
}

TEST(Options, ToleranceWhoseSquareOverflowsOrUnderflowsIsRejected) {
    // 1e308 crashed (sums of t overflowed); at 1e-202 t*t underflowed to 0 and a 1e-200
    // square vanished as "thinner than the tolerance".
    for (double t : {1e308, 5e307, 1.7e308, 1e145, 1e-202, 1e-150, 5e-324}) {
        const std::string msg = rejection(with_tolerance(t));
        EXPECT_NE(msg.find("out of range"), std::string::npos) << "t=" << t << ": '" << msg << "'";
    }
    for (double t : {k_min_tolerance, k_max_tolerance, 1e-140, 1e140}) {
        EXPECT_EQ(validate(with_tolerance(t)), "") << "t=" << t;
    }
    EXPECT_GT(k_min_tolerance * k_min_tolerance, std::numeric_limits<double>::min() * 0x1p+40);
    EXPECT_LT(k_max_tolerance * k_max_tolerance * 0x1p+40, std::numeric_limits<double>::max());
}

TEST(Options, ExtremeButAcceptedTolerancesSnapCorrectly) {
    // At both ends of the range the engine snaps like at t = 1: a square of 10t stays, two
    // vertices 0.3t apart merge, a sliver of 0.2t between neighbours closes.
    for (double t : {k_min_tolerance, 1e-140, 1e140, k_max_tolerance}) {
        std::vector<Feature> in{square(1, 0, 0, 10 * t), square(2, 10.2 * t, 0, 10 * t), square(3, 0, 10.3 * t, 10 * t)};
        const CheckedRun run = snap_and_check(in, options_at(t), 0);
        EXPECT_TRUE(contract_holds(run.report, t)) << "t=" << t;
        EXPECT_EQ(run.report.n_out, 3u) << "t=" << t;
        EXPECT_EQ(run.result.problems.size(), 0u) << "t=" << t << "\n" << problem_lines(run.result.problems);
    }
}

TEST(Options, CoordinatesBeyond2To500AreHugeAtAnyTolerance) {
    // At t = 1e144 a coordinate of 1e155 is within 2^44 t, but its squared differences
    // (1e310) overflow: the feature is rejected with 109, the other one snapped.
    const SnapResult r = snap({square(1, 1e155, 1e155, 1e145), square(2, 0, 0, 1e145)}, with_tolerance(1e144));
    EXPECT_TRUE(has_problem(r, 1, ProblemCode::huge_coordinate)) << problem_lines(r.problems);
    EXPECT_TRUE(r.features[0].geometry.empty());
    EXPECT_FALSE(r.features[1].geometry.empty());
    EXPECT_EQ(r.problems.size(), 1u) << problem_lines(r.problems);
}

TEST(Options, DefaultOptionsAreRejectedBecauseToleranceIsUnset) {
    EXPECT_NE(rejection(SnapOptions{}).find("tolerance"), std::string::npos);
}

TEST(Options, EdgeSeparationOutsideZeroOneIsRejected) {
    for (double e : {0.0, -0.5, 1.5, nan}) {
        SnapOptions o = with_tolerance(1.0);
        o.edge_separation = e;
        EXPECT_NE(rejection(o).find("edge_separation"), std::string::npos) << "e=" << e;
    }
}

TEST(Options, SliverFactorOutsideZeroOneIsRejected) {
    for (double s : {-0.1, 1.1, nan}) {
        SnapOptions o = with_tolerance(1.0);
        o.sliver_factor = s;
        EXPECT_NE(rejection(o).find("sliver_factor"), std::string::npos) << "s=" << s;
    }
}

TEST(Options, GridMustBeNonNegativeAndAtMostAQuarterOfTolerance) {
    for (double g : {-0.1, 0.3, nan, inf}) {
        SnapOptions o = with_tolerance(1.0);
        o.grid = g;
        EXPECT_NE(rejection(o).find("grid"), std::string::npos) << "g=" << g;
    }
}

TEST(Options, MaxDriftFactorMustBeFiniteAndPositive) {
    for (double d : {0.0, -1.0, nan, inf}) {
        SnapOptions o = with_tolerance(1.0);
        o.max_drift_factor = d;
        EXPECT_NE(rejection(o).find("max_drift_factor"), std::string::npos) << "d=" << d;
    }
}

TEST(Options, BoundaryValuesAreAccepted) {
    SnapOptions o = with_tolerance(1e-12);
    o.edge_separation = 1.0;
    o.sliver_factor = 0.0;
    o.grid = o.tolerance / 4;
    EXPECT_EQ(validate(o), "");
    EXPECT_EQ(rejection(o), "");
}

TEST(Options, EmptyInputGivesAnEmptyResult) {
    const SnapResult r = snap({}, with_tolerance(1.0));
    EXPECT_TRUE(r.features.empty());
    EXPECT_TRUE(r.problems.empty());
}

} // namespace
} // namespace trisnap
