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
