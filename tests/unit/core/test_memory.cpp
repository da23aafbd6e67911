// The engine's memory habits that no output shows: the searches' per-vertex scratch is dropped
// after the snapper and comes back if a search needs it, and the output's rings carry no spare
// capacity (closing a ring once doubled every ring's allocation: about 40 MB on Andorra x43).
// Peak memory itself is measured by bench_pipeline (peak_mb) and bench/estimates, not here.
#include "snap_harness.hpp"

#include "core/mesh.hpp"
#include "core/snapper.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace trisnap {
namespace {

std::vector<std::pair<double, std::uint32_t>> near_sorted(detail::Mesh& mesh, std::uint32_t v, double r2)
{
    std::vector<std::pair<double, std::uint32_t>> vertices;
    std::vector<detail::EdgeHit> edges;
    mesh.search_point(v, r2, r2 / 4, vertices, edges);
    std::sort(vertices.begin(), vertices.end());
    return vertices;
}

// A search after release_search_scratch() allocates the scratch again and finds what it found
// before, for every vertex; the snapper then runs on the same mesh to its verified fix-point.
TEST(EngineMemory, SearchesAfterTheScratchIsReleasedFindTheSame)
{
    const double t = 0.05;
    const std::vector<Feature> in = near_degenerate_polygons(40, 10.0, t, 11);
    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
    detail::Mesh mesh(clean, t);
    const auto n = static_cast<std::uint32_t>(mesh.vertex_slots());
    ASSERT_GT(n, 200u);
    const double r2 = 16 * t * t;
    std::vector<std::vector<std::pair<double, std::uint32_t>>> before;
    std::size_t found = 0;
    for (std::uint32_t v = 0; v < n; ++v) {
        before.push_back(near_sorted(mesh, v, r2));
        found += before.back().size();
    }
    EXPECT_GT(found, n) << "the radius must reach neighbours";
    mesh.release_search_scratch();
    for (std::uint32_t v = 0; v < n; ++v) {
        EXPECT_EQ(near_sorted(mesh, v, r2), before[v]) << "vertex " << v;
    }
    mesh.release_search_scratch();
    detail::SnapperParams params;
    params.vertex_threshold = t;
    params.edge_threshold = t / 2;
    params.sliver_threshold = t / 2;
    params.max_operations = 20 * mesh.vertex_slots() + 1000;
    params.verify = true;
    const detail::SnapperOutcome out = detail::run_snapper(mesh, params);
    EXPECT_GT(out.merges + out.splits, 10u) << "the case must make the snapper edit";
    EXPECT_TRUE(out.converged);
    EXPECT_EQ(out.fixpoint_misses, 0u);
}

// A face keeps its stamp in 31 bits (a 64-byte face): the counter wraps at 2^31 and clears every
// mark. Searches on both sides of the wrap find what they find far from it; with the wrap at
// 2^32 a stored stamp would lose its top bit and never match, and the walks would revisit faces.
TEST(EngineMemory, SearchesAcrossTheStampWrapFindTheSame)
{
    const double t = 0.05;
    const std::vector<Feature> in = near_degenerate_polygons(20, 5.0, t, 3);
    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
    detail::Mesh mesh(clean, t);
    const auto n = static_cast<std::uint32_t>(mesh.vertex_slots());
    ASSERT_GT(n, 100u);
    const double r2 = 16 * t * t;
    std::vector<std::vector<std::pair<double, std::uint32_t>>> before;
    for (std::uint32_t v = 0; v < n; ++v) {
        before.push_back(near_sorted(mesh, v, r2));
    }
    mesh.set_stamps_used(cdt::k_stamp_limit - n / 2); // the wrap falls halfway through
    std::size_t faces = mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        EXPECT_EQ(near_sorted(mesh, v, r2), before[v]) << "vertex " << v;
    }
    EXPECT_LT(mesh.stamps_used(), n) << "the counter must have wrapped";
    const std::size_t across = mesh.faces_walked() - faces;
    faces = mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        near_sorted(mesh, v, r2);
    }
    EXPECT_EQ(across, mesh.faces_walked() - faces) << "the walks across the wrap visit each face once, as far from it";
}

// Every output ring's allocation is its size: the closing point had room made for it.
TEST(EngineMemory, OutputRingsHoldNoSpareCapacity)
{
    const double t = 0.05;
    const std::vector<Feature> in = perturbed_grid_coverage(12, 12, 1.0, 0.1, 5, 3);
    const CheckedRun run = snap_and_check(in, options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    std::size_t rings = 0;
    for (const FeatureOutput& f : run.result.features) {
        for (const Polygon& p : f.geometry.polygons) {
            for (const Path& ring : p.rings) {
                ++rings;
                EXPECT_EQ(ring.capacity(), ring.size()) << "feature " << f.id;
            }
        }
    }
    EXPECT_EQ(rings, in.size());
}

} // namespace
} // namespace trisnap
