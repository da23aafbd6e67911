// Adversarial inputs: the engine's work must stay near O(n log n) whatever the tolerance.
// Checked by counts that do not depend on the machine's load: the snapper's operation count
// (faces its searches walked) when the input doubles at large t (n log n gives about 2.1x,
// quadratic 4x, cubic 8x), and the queue's peak against the vertices. The time target (the
// large-t run within 10x of the small-t run of the same input) lives in bench/adversarial.
#include "snap_harness.hpp"

#include "generators.hpp"
#include "mesh_harness.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <ctime>
#include <iostream>

namespace trisnap {
namespace {

struct Cost {
    double cpu_s = 0;
    std::size_t faces = 0;
    std::size_t merges = 0;
};

Cost cost_of(const std::vector<Feature>& features, double t) {
    const std::clock_t start = std::clock();
    const SnapResult result = snap(features, options_at(t));
    Cost c;
    c.cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    c.faces = result.stats.faces_visited;
    c.merges = result.stats.merges;
    EXPECT_FALSE(result.features.empty());
    return c;
}

const AdversarialCase& find_case(const std::vector<AdversarialCase>& cases, const std::string& name) {
    for (const AdversarialCase& c : cases) {
        if (name == c.name) {
            return c;
        }
    }
    throw std::runtime_error("no adversarial case " + name);
}

class AdversarialSlow : public ::testing::TestWithParam<const char*> {};

// Vertices closer than t along a line or a circle: at the large t (thousands of merges) doubling
// the input must not more than about double the snapper's work (faces its searches walked, a
// count that does not depend on the machine's load; n log n gives about 2.1x, quadratic 4x).
// The target, CPU within 10x of the small-t run, is measured by bench/adversarial.
TEST_P(AdversarialSlow, WorkAtLargeToleranceGrowsNearLinearly) {
    const std::vector<AdversarialCase> halves = adversarial_cases(0.5);
    const std::vector<AdversarialCase> fulls = adversarial_cases(1.0);
    const AdversarialCase& half = find_case(halves, GetParam());
    const AdversarialCase& full = find_case(fulls, GetParam());
    const Cost a = cost_of(half.features, half.large_t);
    const Cost b = cost_of(full.features, full.large_t);
    std::cout << full.name << " x2: faces " << a.faces << " -> " << b.faces << ", merges " << a.merges << " -> "
              << b.merges << ", CPU " << a.cpu_s << " -> " << b.cpu_s << " s\n";
    EXPECT_GT(b.merges, vertex_count(full.features) / 10) << "the large tolerance must make real work";
    EXPECT_LE(b.faces, 3 * a.faces);
}

INSTANTIATE_TEST_SUITE_P(Inputs, AdversarialSlow,
                         ::testing::Values("densified_square", "circle", "circle_jittered", "squares_framed"));

// Tolerance ten times the features: every square collapses and the squares merge into clusters.
// Doubling the squares must not more than about double the snapper's searches (measured 2.2-2.4x).
TEST(AdversarialScalingSlow, SquaresAtLargeToleranceScaleNearLinearly) {
    const std::vector<AdversarialCase> cases = adversarial_cases(1.0);
    std::vector<Cost> costs;
    for (const AdversarialCase& c : cases) {
        if (std::string(c.name) == "squares") {
            costs.push_back(cost_of(c.features, c.large_t));
        }
    }
    ASSERT_EQ(costs.size(), 3u);
    for (std::size_t i = 1; i < costs.size(); ++i) {
        std::cout << "squares x2: faces " << costs[i - 1].faces << " -> " << costs[i].faces << ", CPU "
                  << costs[i - 1].cpu_s << " -> " << costs[i].cpu_s << " s\n";
        EXPECT_LE(costs[i].faces, 3 * costs[i - 1].faces);
    }
}

// The snapper's queue holds one merge event per vertex, not one per pair within t, and face
// events for each vertex's candidate, not one per trivial face: at t = 10, 400 unit squares (1,600 vertices) lie within t of hundreds of others each, about 10^5 pairs,
// which the pair-by-pair queue held (and Andorra at 0.01 degrees ran out of memory on). Run on
// the engine's own mesh so the queue's peak is visible; the fix-point is verified as in every
// engine test.
TEST(Adversarial, QueueStaysLinearInTheVerticesWhenEverythingIsWithinT) {
    const std::vector<Feature> in = random_small_squares(400, 1.0, 30.0, 7);
    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> clean = detail::clean_input(in, 10.0, problems);
    detail::Mesh mesh(clean, 10.0);
    const std::size_t vertices = mesh.vertex_slots();
    std::size_t pairs_within_t = 0;
    for (std::uint32_t a = 0; a < vertices; ++a) {
        for (std::uint32_t b = a + 1; b < vertices; ++b) {
            const double dx = mesh.vertex(a).x - mesh.vertex(b).x;
            const double dy = mesh.vertex(a).y - mesh.vertex(b).y;
            pairs_within_t += dx * dx + dy * dy <= 100.0 ? 1 : 0;
        }
    }
    detail::SnapperParams params;
    params.vertex_threshold = 10.0;
    params.edge_threshold = 5.0;
    params.sliver_threshold = 5.0;
    params.max_operations = 100 * vertices;
    params.verify = true;
    const detail::SnapperOutcome out = detail::run_snapper(mesh, params);
    std::cout << vertices << " vertices, " << pairs_within_t << " pairs within t, queue peak " << out.peak_queue
              << ", " << out.merges << " merges, " << out.face_events << " face events\n";
    EXPECT_GT(pairs_within_t, 50 * vertices) << "the case must be dense in pairs";
    EXPECT_GT(out.merges, vertices / 2);
    EXPECT_TRUE(out.converged);
    EXPECT_EQ(out.fixpoint_misses, 0u);
    EXPECT_LE(out.peak_queue, 16 * vertices);
    // Face collapses too are queued as each vertex's candidate, not face by face (the comment
    // at Snapper::check_face): 4,985 face events here, 13,899 with every trivial face queued.
    EXPECT_LE(out.face_events, 3 * vertices);
}

// The long edges' grid (core/long_edges.hpp) is built where walks held at the edge radius grow
// costly and nowhere else: squares packed inside a frame of long edges at t = 10 build it (and
// the fix-point check, a full scan whose walks take no help from the grid, finds no event
// left), the same squares without the frame, or at t = 0.01, never build it. What this does not
// show: that the grid's edges are needed here. With them dropped from the walks the check still
// found nothing (the frame is far from the squares, and a frame 2 from them, or slivers off,
// changed nothing): the grid's answers are checked by LongEdgeIndex's brute-force test.
TEST(Adversarial, LongEdgesGridIsBuiltOnlyWhereItPays) {
    const std::vector<AdversarialCase> cases = adversarial_cases(1.0);
    const std::vector<Feature>& framed = find_case(cases, "squares_framed").features;
    const std::vector<Feature> unframed(framed.begin(), framed.end() - 1);
    const auto run = [](const std::vector<Feature>& in, double t, bool& indexed) {
        std::vector<Problem> problems;
        const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
        detail::Mesh mesh(clean, t);
        detail::SnapperParams params;
        params.vertex_threshold = t;
        params.edge_threshold = t / 2;
        params.sliver_threshold = t / 2;
        params.max_operations = 100 * mesh.vertex_slots();
        params.verify = true;
        const detail::SnapperOutcome out = detail::run_snapper(mesh, params);
        indexed = mesh.long_edges_indexed();
        return out;
    };
    bool indexed = false;
    const detail::SnapperOutcome out = run(framed, 10.0, indexed);
    EXPECT_TRUE(indexed) << "the frame's edges must make the walks costly enough";
    EXPECT_TRUE(out.converged);
    EXPECT_GT(out.merges, vertex_count(framed) / 2);
    EXPECT_EQ(out.fixpoint_misses, 0u);
    run(unframed, 10.0, indexed);
    EXPECT_FALSE(indexed) << "no long edge: no grid";
    run(framed, 0.01, indexed);
    EXPECT_FALSE(indexed) << "walks of a few faces: no grid";
}

// An exact circle with 16 vertices per t. A merged vertex sits inside the circle by the sagitta,
// and in a Delaunay triangulation of nearly co-circular points such a vertex neighbours nearly
// the whole circle (degree 19,996 of 20,000 measured). CGAL refills the hole of a removed vertex
// with d^2 in-circle tests, so with every merge paying for a hub the run was quadratic (10.6 s at
// 20,000 vertices, 925 s at 10^6). The engine bounds an insertion's flips, so such a vertex does
// not become a hub, and removes a hub by rounds of flips first (core/mesh_hubs.cpp): the
// hole-filling work (the sum of the squared degrees removed) must grow near linearly with the
// circle (it grew 5.2x per doubling without the bounds), the bounds must really have been hit,
// the fix-point must hold, and the result keep the contract.
TEST(Adversarial, HubsOfAnExactCircleAreRemovedAtBoundedCost) {
    constexpr double t = 0.01;
    struct Run {
        std::size_t work = 0, hubs = 0, merges = 0;
        bool bounded = false;
    };
    const auto run = [&](int n) {
        // Spacing 2 pi r / n = 6.3e-4, a sixteenth of t.
        const std::vector<Feature> in = {circle(1, n, n * 1e-4, 0.0, 1)};
        std::vector<Problem> problems;
        const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
        detail::Mesh mesh(clean, t);
        const detail::SnapperOutcome out = run_snapper_at(mesh, t);
        EXPECT_TRUE(out.converged) << n;
        EXPECT_EQ(out.fixpoint_misses, 0u) << n;
        // A valid triangulation (CGAL's check of the plain one: the Delaunay one's also wants
        // every edge Delaunay, which the bounds give up).
        EXPECT_TRUE(mesh.tri().cdt::CtBase::is_valid()) << n;
        return Run{mesh.removal_work(), mesh.hub_removals(), out.merges, mesh.bounds_hit()};
    };
    const Run a = run(10'000);
    const Run b = run(20'000);
    std::cout << "circle x2: removal work " << a.work << " -> " << b.work << ", hub removals " << a.hubs << " -> "
              << b.hubs << ", merges " << a.merges << " -> " << b.merges << "\n";
    EXPECT_GT(b.merges, 15'000u) << "the tolerance must make real work";
    EXPECT_TRUE(a.bounded && b.bounded) << "the circle must take the edits off CGAL's path, or this test checks nothing";
    EXPECT_LE(b.work, 3 * a.work);
    const std::vector<Feature> in = {circle(1, 20'000, 2.0, 0.0, 1)};
    const CheckedRun checked = snap_and_check(in, options_at(t), in.size());
    ASSERT_EQ(checked.result.features.size(), 1u);
    EXPECT_FALSE(checked.result.features[0].geometry.empty());
}

// Hubs beside constraints: two overlapping exact circles, a third inside the first as its hole,
// and a straight line through all of them, each dense (16 vertices per t). The hub removals and
// the bounded insertions then happen where constrained edges cross the circles' insides; the
// engine must keep the fix-point and the contract (valid, separated, accounted, drift) there.
TEST(Adversarial, HubsBesideConstraintsKeepTheContract) {
    constexpr double t = 0.01;
    std::vector<Feature> in;
    Feature a = circle(1, 5'000, 0.5, 0.0, 1);
    Feature hole = circle(0, 2'000, 0.2, 0.0, 1);
    std::reverse(hole.geometry.polygons[0].rings[0].begin(), hole.geometry.polygons[0].rings[0].end());
    a.geometry.polygons[0].rings.push_back(hole.geometry.polygons[0].rings[0]);
    in.push_back(a);
    Feature b = circle(2, 5'000, 0.5, 0.0, 2);
    for (Coord& c : b.geometry.polygons[0].rings[0]) {
        c.x += 0.3;
    }
    in.push_back(b);
    Feature line;
    line.id = 3;
    line.geometry.type = Geometry::Type::LineString;
    line.geometry.lines.push_back(Path{Coord{-0.7, 0.013}, Coord{1.1, -0.021}});
    in.push_back(line);

    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
    detail::Mesh mesh(clean, t);
    const detail::SnapperOutcome out = run_snapper_at(mesh, t);
    std::cout << "circles and a line: " << mesh.hub_removals() << " hub removals, " << out.merges << " merges, "
              << out.splits << " splits\n";
    EXPECT_GT(mesh.hub_removals(), 0u) << "the case must make hubs, or this test checks nothing";
    EXPECT_TRUE(out.converged);
    EXPECT_EQ(out.fixpoint_misses, 0u);
    EXPECT_TRUE(mesh.tri().cdt::CtBase::is_valid());

    const CheckedRun checked = snap_and_check(in, options_at(t), in.size());
    EXPECT_TRUE(contract_holds(checked.report, t)) << checked.report.summary();
    ASSERT_EQ(checked.result.features.size(), in.size());
    for (const FeatureOutput& f : checked.result.features) {
        EXPECT_FALSE(f.geometry.empty()) << "feature " << f.id;
    }
}

// The bounded edits lowered until they are everywhere (hubs above degree 6, two flips per
// insertion): the triangulation is then far from Delaunay on every input, which is where a
// removal by CGAL's Delaunay hole fill can make overlapping faces (seen once, in a stress run of
// the whole suite with the bounds compiled in at 6 and 2, building included; these inputs, with
// the bounds set after the build, did not show it: this test guards the bounded paths, it is
// not that failure's reproduction). On near-degenerate
// polygons, a tolerance larger than the features and dense circles, the triangulation must stay
// valid after every edit (the mesh checks and throws) and the snapper reach its fix-point.
TEST(Adversarial, LoweredEditBoundsKeepTheTriangulationValid) {
    struct Input {
        const char* name;
        std::vector<Feature> features;
        double t;
    };
    std::vector<Input> inputs;
    for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
        inputs.push_back({"near-degenerate", near_degenerate_polygons(200, 200.0, 1.0, seed), 1.0});
    }
    inputs.push_back({"near-degenerate, tiny", near_degenerate_polygons(200, 2e-4, 1e-6, 9), 1e-6});
    inputs.push_back({"squares at t = 10", random_small_squares(300, 1.0, 26.0, 7), 10.0});
    std::vector<Feature> circles = {circle(1, 3'000, 0.3, 0.0, 1), circle(2, 3'000, 0.3, 0.0, 2)};
    for (Coord& c : circles[1].geometry.polygons[0].rings[0]) {
        c.x += 0.2;
    }
    inputs.push_back({"circles", circles, 0.01});
    for (const Input& input : inputs) {
        std::vector<Problem> problems;
        const std::vector<detail::CleanFeature> clean = detail::clean_input(input.features, input.t, problems);
        detail::Mesh mesh(clean, input.t);
        mesh.set_edit_bounds(6, 2, true); // and CGAL's validity check after every edit
        const detail::SnapperOutcome out = run_snapper_at(mesh, input.t);
        std::cout << input.name << ": " << mesh.hub_removals() << " hub removals, " << out.merges << " merges, "
                  << out.splits << " splits\n";
        EXPECT_GT(out.merges + out.splits, 0u) << input.name;
        EXPECT_TRUE(out.converged) << input.name;
        EXPECT_EQ(out.fixpoint_misses, 0u) << input.name;
        EXPECT_TRUE(mesh.tri().cdt::CtBase::is_valid()) << input.name;
    }
}

TEST(Adversarial, ToleranceLargerThanTheWholeLayerCollapsesEverythingWithoutTriangulating) {
    // Every vertex within t of every other: no two output vertices could be t apart, so every
    // feature collapses, and the engine says so at once (Andorra at 1 degree ran out of memory
    // at 12.7 GB: its queue held an event per pair of vertices). 2,000 squares and a line in a
    // 1 x 1 box (diagonal 1.41) at t = 1.5.
    std::vector<Feature> in = random_small_squares(2000, 0.01, 0.99, 3);
    in.push_back(dense_line(5000, 200, 0.005, 0.001, 4));
    const CheckedRun run = snap_and_check(in, options_at(1.5), in.size());
    EXPECT_EQ(run.result.stats.triangulation_vertices, 0u) << "the triangulation was built";
    EXPECT_EQ(run.result.stats.collapsed_features, in.size());
    for (const FeatureOutput& f : run.result.features) {
        EXPECT_TRUE(f.geometry.empty()) << "feature " << f.id;
    }
    EXPECT_EQ(count_code(run.result, ProblemCode::collapsed_polygon), 2000u);
    EXPECT_EQ(count_code(run.result, ProblemCode::collapsed_line), 1u);
    EXPECT_EQ(run.report.n_missing, 0u) << run.report.summary(); // each one excused by 201/202
    // Just below the diagonal the engine runs as always, and keeps the contract.
    const std::vector<Feature> few(in.begin(), in.begin() + 40);
    const CheckedRun full = snap_and_check(few, options_at(0.5), few.size());
    EXPECT_GT(full.result.stats.triangulation_vertices, 0u);
    EXPECT_TRUE(contract_holds(full.report, 0.5)) << full.report.summary();
}

} // namespace
} // namespace trisnap
