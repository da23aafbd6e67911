// The engine's memory habits that no output shows: the searches' per-vertex scratch is dropped
// after the snapper and comes back if a search needs it, and the output's rings carry no spare
// capacity (closing a ring once doubled every ring's allocation: 34 MB of heap on Andorra x43).
// Peak memory itself is measured by bench_pipeline (peak_mb) and bench/estimates, not here.
#include "snap_harness.hpp"

#include "generators.hpp"
#include "mesh_harness.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace trisnap {
namespace {

using Near = std::vector<std::pair<double, std::uint32_t>>;

// A mesh of near-degenerate polygons at t and, for every vertex, the vertices a search within
// 4t finds (sorted), searched once before the test does anything to the mesh.
struct SearchedMesh {
    static constexpr double t = 0.05;
    static constexpr double r2 = 16 * t * t;
    std::vector<detail::CleanFeature> clean;
    detail::Mesh mesh;
    std::vector<Near> before;

    SearchedMesh(int polygons, double scale, std::uint64_t seed)
        : clean(cleaned(near_degenerate_polygons(polygons, scale, t, seed))), mesh(clean, t)
    {
        for (std::uint32_t v = 0; v < vertices(); ++v) {
            before.push_back(search(v));
        }
    }
    std::uint32_t vertices() const { return static_cast<std::uint32_t>(mesh.vertex_slots()); }
    Near search(std::uint32_t v)
    {
        Near near;
        std::vector<detail::EdgeHit> edges;
        mesh.search_point(v, r2, r2 / 4, near, edges);
        std::sort(near.begin(), near.end());
        return near;
    }
    static std::vector<detail::CleanFeature> cleaned(const std::vector<Feature>& in)
    {
        std::vector<Problem> problems;
        return detail::clean_input(in, t, problems);
    }
};

// A search after release_search_scratch() allocates the scratch again and finds what it found
// before, for every vertex; the snapper then runs on the same mesh to its verified fix-point.
TEST(EngineMemory, SearchesAfterTheScratchIsReleasedFindTheSame)
{
    SearchedMesh m(40, 10.0, 11);
    ASSERT_GT(m.vertices(), 200u);
    std::size_t found = 0;
    for (const Near& near : m.before) found += near.size();
    EXPECT_GT(found, m.vertices()) << "the radius must reach neighbours";
    m.mesh.release_search_scratch();
    for (std::uint32_t v = 0; v < m.vertices(); ++v) {
        EXPECT_EQ(m.search(v), m.before[v]) << "vertex " << v;
    }
    m.mesh.release_search_scratch();
    const detail::SnapperOutcome out = run_snapper_at(m.mesh, SearchedMesh::t);
    EXPECT_GT(out.merges + out.splits, 10u) << "the case must make the snapper edit";
    EXPECT_TRUE(out.converged);
    EXPECT_EQ(out.fixpoint_misses, 0u);
}

// A face keeps its stamp in 31 bits (a 64-byte face): the counter wraps at 2^31 and clears every
// mark. Searches on both sides of the wrap find what they find far from it; with the wrap at
// 2^32 a stored stamp would lose its top bit and never match, and the walks would revisit faces.
TEST(EngineMemory, SearchesAcrossTheStampWrapFindTheSame)
{
    SearchedMesh m(20, 5.0, 3);
    const std::uint32_t n = m.vertices();
    ASSERT_GT(n, 100u);
    m.mesh.set_stamps_used(cdt::k_stamp_limit - n / 2); // the wrap falls halfway through
    std::size_t faces = m.mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        EXPECT_EQ(m.search(v), m.before[v]) << "vertex " << v;
    }
    EXPECT_LT(m.mesh.stamps_used(), n) << "the counter must have wrapped";
    const std::size_t across = m.mesh.faces_walked() - faces;
    faces = m.mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        m.search(v);
    }
    EXPECT_EQ(across, m.mesh.faces_walked() - faces) << "the walks across the wrap visit each face once, as far from it";
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
