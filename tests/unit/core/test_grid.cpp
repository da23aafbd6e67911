// SnapOptions::grid: every output coordinate is a multiple of g, and the contract still holds
// at t once rounded (the engine snaps with margins so that rounding cannot break it).
#include "snap_harness.hpp"

#include "core/wkt.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace trisnap {
namespace {

/// Coordinates that are not multiples of g within 1e-9 relative, as text (first few).
std::string off_grid(const SnapResult& r, double g) {
    std::ostringstream out;
    int n = 0;
    auto check = [&](std::int64_t id, const Coord& c) {
        for (double v : {c.x, c.y}) {
            const double k = std::round(v / g);
            if (std::abs(v - k * g) > 1e-9 * std::max(std::abs(v), g) && n++ < 5)
                out << "id " << id << ": " << v << " is not a multiple of " << g << "\n";
        }
    };
    for (const FeatureOutput& f : r.features) {
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& ring : p.rings)
                for (const Coord& c : ring)
                    check(f.id, c);
        for (const Path& l : f.geometry.lines)
            for (const Coord& c : l)
                check(f.id, c);
    }
    return out.str();
}

/// `max_flagged`: features the engine may flag, as measured when the bound was introduced.
void expect_on_grid_with_contract(const std::vector<Feature>& in, double t, double g, std::size_t max_flagged) {
    const CheckedRun run = snap_and_check(in, options_at(t, g), max_flagged);
    EXPECT_EQ(off_grid(run.result, g), "");
    EXPECT_TRUE(contract_holds(run.report, t)) << "t=" << t << " g=" << g;
}

TEST(Grid, PerturbedCoverageAtATenthOfT) {
    for (double t : {0.05, 0.2, 1.0})
        expect_on_grid_with_contract(perturbed_grid_coverage(12, 12, 10.0, 0.2, 11, 3), t, t / 10, 0);
}

TEST(Grid, NearDegeneratePolygonsAtATenthOfT) {
    const std::size_t flagged[] = {43, 43, 29}; // seeds 1, 2, 3
    for (std::uint64_t seed : {1u, 2u, 3u})
        expect_on_grid_with_contract(near_degenerate_polygons(150, 200.0, 1.0, seed), 1.0, 0.1, flagged[seed - 1]);
}

TEST(Grid, CoarsestAllowedGridIsAQuarterOfT) {
    expect_on_grid_with_contract(near_degenerate_polygons(150, 200.0, 1.0, 4), 1.0, 0.25, 41);
}

TEST(Grid, NonDyadicGridStep) {
    // 0.3 is not exact in binary: "multiple of g" is checked within 1e-9 relative.
    expect_on_grid_with_contract(perturbed_grid_coverage(8, 8, 10.0, 0.2, 5, 2), 1.2, 0.3, 0);
}

TEST(Grid, GeographicCoordinatesAtMicroDegrees) {
    std::vector<Feature> in = perturbed_grid_coverage(10, 10, 1e-4, 0.2, 9, 2);
    for (Feature& f : in)
        for (Polygon& p : f.geometry.polygons)
            for (Path& r : p.rings)
                for (Coord& c : r)
                    c.x += 4.9, c.y += 52.3; // Delft, in degrees
    expect_on_grid_with_contract(in, 1e-6, 1e-7, 0);
}

} // namespace
} // namespace trisnap
