// Random near-degenerate polygons (near-coincident vertices, spikes, holes, slivers, vertices
// just outside a neighbour's edge), vertex clusters and dense lines: the contract on every
// output, over several seeds and tolerances.
#include "snap_harness.hpp"

#include "core/wkt.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <cctype>
#include <set>
#include <sstream>
#include <string>

namespace trisnap {
namespace {

struct DegenerateCase {
    int n;
    double scale;
    double t;
    std::uint64_t seed;
    /// Features the engine may flag (about a third collapse partly at this density), as
    /// measured when the bound was introduced: more means the engine got worse here.
    std::size_t max_flagged;
};

std::ostream& operator<<(std::ostream& os, const DegenerateCase& c) {
    return os << "n=" << c.n << " scale=" << c.scale << " t=" << c.t << " seed=" << c.seed;
}

std::string case_name(const ::testing::TestParamInfo<DegenerateCase>& info) {
    const DegenerateCase& c = info.param;
    std::ostringstream name;
    name << "n" << c.n << "_t" << c.t << "_seed" << c.seed;
    std::string out = name.str();
    for (char& ch : out)
        if (!std::isalnum(static_cast<unsigned char>(ch)))
            ch = '_';
    return out;
}

void run_degenerate(const DegenerateCase& c) {
    const std::vector<Feature> in = near_degenerate_polygons(c.n, c.scale, c.t, c.seed);
    const CheckedRun run = snap_and_check(in, options_at(c.t), c.max_flagged);
    std::cout << figures_line("near_degenerate n=" + std::to_string(c.n) + " seed=" +
                                  std::to_string(c.seed) + " (" + std::to_string(vertex_count(in)) + " vertices)",
                              run, c.t) << "\n";
    EXPECT_TRUE(contract_holds(run.report, c.t));
}

class NearDegenerate : public ::testing::TestWithParam<DegenerateCase> {};
class NearDegenerateSlow : public ::testing::TestWithParam<DegenerateCase> {};

TEST_P(NearDegenerate, ContractHolds) { run_degenerate(GetParam()); }
TEST_P(NearDegenerateSlow, ContractHolds) { run_degenerate(GetParam()); }

// Density (polygons per scale^2) is kept about the same, so larger n means more vertices.
INSTANTIATE_TEST_SUITE_P(Seeds, NearDegenerate, ::testing::Values(
    DegenerateCase{50, 100.0, 1.0, 1, 22}, DegenerateCase{50, 100.0, 1.0, 2, 16},
    DegenerateCase{50, 100.0, 1.0, 3, 10}, DegenerateCase{200, 200.0, 1.0, 4, 60},
    DegenerateCase{200, 200.0, 1.0, 5, 57}, DegenerateCase{200, 200.0, 1.0, 6, 54},
    DegenerateCase{200, 2.0, 0.01, 7, 64}, DegenerateCase{200, 0.002, 1e-5, 8, 63},
    DegenerateCase{200, 2e-4, 1e-6, 9, 73}, DegenerateCase{200, 2e6, 1e4, 10, 49},
    DegenerateCase{1000, 450.0, 1.0, 11, 284}), case_name);

// Seed 13: 2427 with the lean engine (its crossings round to the nearest double, the old one's
// did not; one more feature, id 7999, ends with a reported collapse), 2426 before.
INSTANTIATE_TEST_SUITE_P(Seeds, NearDegenerateSlow, ::testing::Values(
    DegenerateCase{1000, 450.0, 1.0, 12, 286}, DegenerateCase{1000, 450.0, 0.1, 14, 162},
    DegenerateCase{8000, 1270.0, 1.0, 13, 2427}), case_name);

TEST(NearDegenerate, GeographicCoordinatesFarFromTheOrigin) {
    // Degrees near Delft at a 10 cm tolerance: large coordinates, tiny t.
    std::vector<Feature> in = near_degenerate_polygons(200, 2e-4, 1e-6, 21);
    for (Feature& f : in)
        for (Polygon& p : f.geometry.polygons)
            for (Path& r : p.rings)
                for (Coord& c : r)
                    c.x += 4.35, c.y += 52.0;
    const CheckedRun run = snap_and_check(in, options_at(1e-6), 48);
    EXPECT_TRUE(contract_holds(run.report, 1e-6));
}

/// The vertices common to every output ring.
std::set<std::pair<double, double>> common_vertices(const SnapResult& r) {
    std::set<std::pair<double, double>> common;
    bool first = true;
    for (const FeatureOutput& f : r.features) {
        std::set<std::pair<double, double>> mine;
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& ring : p.rings)
                for (const Coord& c : ring)
                    mine.insert({c.x, c.y});
        if (first)
            common = mine;
        else
            std::erase_if(common, [&](const auto& v) { return !mine.count(v); });
        first = false;
    }
    return common;
}

TEST(VertexCluster, AllInnerCornersMergeIntoOneVertex) {
    for (int k : {3, 5, 8, 12}) {
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            const double t = 1.0;
            const std::vector<Feature> in = vertex_cluster(k, t, seed);
            const CheckedRun run = snap_and_check(in, options_at(t), 0);
            SCOPED_TRACE("k=" + std::to_string(k) + " seed=" + std::to_string(seed));
            EXPECT_TRUE(contract_holds(run.report, t));
            EXPECT_EQ(run.report.n_out, in.size());
            EXPECT_EQ(common_vertices(run.result).size(), 1u);
        }
    }
}

TEST(VertexCluster, AtTinyAndHugeScales) {
    for (double t : {1e-7, 1e-3, 1e5}) {
        const CheckedRun run = snap_and_check(vertex_cluster(6, t, 4), options_at(t), 0);
        EXPECT_TRUE(contract_holds(run.report, t)) << "t=" << t;
        EXPECT_EQ(common_vertices(run.result).size(), 1u) << "t=" << t;
    }
}

TEST(DenseLine, ChainOfPointsCloserThanTMergesWithoutDrifting) {
    for (double spacing : {0.1, 0.3, 0.6, 0.9}) {
        const CheckedRun run = snap_and_check({dense_line(1, 200, spacing, 0.2, 3)}, options_at(1.0), 0);
        EXPECT_TRUE(contract_holds(run.report, 1.0)) << "spacing=" << spacing;
        EXPECT_FALSE(run.result.features[0].geometry.empty()) << "spacing=" << spacing;
    }
}

TEST(DenseLine, ParallelDenseLinesCloserThanT) {
    std::vector<Feature> in;
    for (int i = 0; i < 4; ++i) {
        Feature f = dense_line(i + 1, 100, 0.4, 0.1, 10 + i);
        for (Coord& c : f.geometry.lines[0])
            c.y += 0.35 * i;
        in.push_back(f);
    }
    const CheckedRun run = snap_and_check(in, options_at(1.0), 0);
    EXPECT_TRUE(contract_holds(run.report, 1.0));
}

} // namespace
} // namespace trisnap
