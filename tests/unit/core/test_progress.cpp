// The engine's progress and cancel callback (SnapOptions::progress): monotone counts of input
// vertices with a total, ending at the total, calls often enough for a bar on a big run; the
// result does not depend on it; an exception thrown from it stops the run and leaves snap() as is.
#include "snap_harness.hpp"

#include "core/snap.hpp"
#include "core/wkt.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace trisnap {
namespace {

struct Call {
    std::size_t done;
    std::size_t total;
};

SnapOptions options_at(double t)
{
    SnapOptions o;
    o.tolerance = t;
    return o;
}

std::string all_wkt(const SnapResult& r)
{
    std::string out;
    for (const FeatureOutput& f : r.features) {
        out += std::to_string(f.id) + ":" + to_wkt(f.geometry) + "\n";
    }
    for (const Problem& p : r.problems) {
        out += std::to_string(p.feature_id) + "/" + std::to_string(static_cast<int>(p.code)) + "\n";
    }
    return out;
}

// ~60k vertices with snapping work to do (jitter near t), so every step has something to count.
std::vector<Feature> layer() { return perturbed_grid_coverage(60, 60, 1.0, 0.02, 7, 3, 0.004); }

// A long snapping cascade on a small input: 2,000 unit squares at t = 10 merge thousands of
// times while the vertex count (8,000 vertices, under two strides) hardly moves. The callback must
// still come during the snapping step, so that Ctrl-C is heard inside the cascade (it used to
// wait for its end: 41 s on Andorra at 0.01 degrees).
TEST(EngineProgress, CallsBackDuringACascadeEvenWhenTheCountStalls)
{
    const std::vector<Feature> features = random_small_squares(2000, 1.0, 67.0, 7);
    std::vector<Call> calls;
    SnapOptions o = options_at(10.0);
    o.progress = [&](std::size_t done, std::size_t total) { calls.push_back({done, total}); };
    const SnapResult watched = snap(features, o);
    ASSERT_GT(watched.stats.merges, 5000u);
    const std::size_t total = watched.stats.input_vertices;
    std::size_t in_snapping = 0; // calls strictly inside the snapping step's share, [50 %, 75 %)
    for (std::size_t i = 0; i < calls.size(); ++i) {
        if (i > 0) {
            EXPECT_GE(calls[i].done, calls[i - 1].done);
        }
        in_snapping += calls[i].done * 2 > total && calls[i].done * 4 < total * 3 ? 1 : 0;
    }
    EXPECT_GE(in_snapping, 4u) << calls.size() << " calls in all";
    EXPECT_EQ(calls.back().done, total);
}

TEST(EngineProgress, CountsInputVerticesMonotoneToTheTotalAndChangesNothing)
{
    const std::vector<Feature> features = layer();
    const SnapResult plain = snap(features, options_at(0.01));
    std::vector<Call> calls;
    SnapOptions o = options_at(0.01);
    o.progress = [&](std::size_t done, std::size_t total) { calls.push_back({done, total}); };
    const SnapResult watched = snap(features, o);

    EXPECT_EQ(all_wkt(watched), all_wkt(plain));
    ASSERT_FALSE(calls.empty());
    const std::size_t total = watched.stats.input_vertices;
    ASSERT_GT(total, 50000u);
    for (std::size_t i = 0; i < calls.size(); ++i) {
        EXPECT_EQ(calls[i].total, total) << "call " << i;
        EXPECT_LE(calls[i].done, total) << "call " << i;
        if (i > 0) {
            EXPECT_GT(calls[i].done, calls[i - 1].done) << "call " << i << " went back or repeated";
        }
    }
    EXPECT_EQ(calls.back().done, total);
    // A stride of 4096 vertices over ~60k: a live bar, not a jump from 0 to the end. Each step
    // (points, constraints, snapping, extraction) reports at least once on its way.
    EXPECT_GE(calls.size(), 10u);
    EXPECT_LE(calls.size(), total / 4096 + 8);
    const std::size_t before_last = calls[calls.size() - 2].done;
    EXPECT_GT(before_last, total / 2) << "the extraction step reported nothing before the end";
}

TEST(EngineProgress, EmptyAndTinyRunsStillEndAtTheirTotal)
{
    std::vector<Call> calls;
    SnapOptions o = options_at(0.1);
    o.progress = [&](std::size_t done, std::size_t total) { calls.push_back({done, total}); };
    snap({}, o);
    ASSERT_EQ(calls.size(), 1u);
    EXPECT_EQ(calls[0].done, 0u);
    EXPECT_EQ(calls[0].total, 0u);

    calls.clear();
    const SnapResult r = snap({square(1, 0, 0, 10)}, o);
    ASSERT_FALSE(calls.empty());
    EXPECT_EQ(calls.back().done, r.stats.input_vertices);
    EXPECT_EQ(calls.back().total, r.stats.input_vertices);
}

struct Stop : std::runtime_error {
    Stop() : std::runtime_error("stop") {}
};

TEST(EngineProgress, ThrowingFromTheCallbackCancelsInEveryStep)
{
    const std::vector<Feature> features = layer();
    std::size_t total = 0;
    {
        SnapOptions o = options_at(0.01);
        o.progress = [&](std::size_t, std::size_t all) { total = all; };
        snap(features, o);
    }
    ASSERT_GT(total, 0u);
    // Stop at a tenth (points/constraints), at 60 % (snapping) and at 90 % (extraction): the
    // exception comes out as thrown, and the callback is not called again after it.
    for (const double at : {0.1, 0.6, 0.9}) {
        std::size_t calls_after = 0;
        bool thrown = false;
        SnapOptions o = options_at(0.01);
        o.progress = [&](std::size_t done, std::size_t) {
            if (thrown) {
                ++calls_after;
            }
            if (static_cast<double>(done) >= at * static_cast<double>(total) && !thrown) {
                thrown = true;
                throw Stop();
            }
        };
        EXPECT_THROW(snap(features, o), Stop) << "at " << at;
        EXPECT_TRUE(thrown) << "at " << at;
        EXPECT_EQ(calls_after, 0u) << "at " << at;
    }
    // The engine holds nothing between runs: a run after the cancelled ones is the same as ever.
    EXPECT_EQ(all_wkt(snap(features, options_at(0.01))), all_wkt(snap(features, options_at(0.01))));
}

} // namespace
} // namespace trisnap
