// A tile whose engine throws (OnError): stop names the tile; skip retries it merged with its
// neighbours (then the output is the untiled one), and what fails again is dropped whole with
// problem 303 per feature while every other feature is exactly the untiled output. Failures are
// injected with TRISNAP_FAIL_TILES (stitch/tile_run.cpp): the engine itself has no known failure.
#include "tiled_check.hpp"

#include "generators.hpp"
#include "spool_input.hpp"
#include "stitch/tiled_snap.hpp"
#include "tiling/work_store.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <set>
#include <string>

namespace trisnap {
namespace {

/// Sets TRISNAP_FAIL_TILES for one scope.
class InjectedFailure {
public:
    explicit InjectedFailure(const std::string& spec) { ::setenv("TRISNAP_FAIL_TILES", spec.c_str(), 1); }
    ~InjectedFailure() { ::unsetenv("TRISNAP_FAIL_TILES"); }
    InjectedFailure(const InjectedFailure&) = delete;
    InjectedFailure& operator=(const InjectedFailure&) = delete;
};

class OnError : public ::testing::Test {
protected:
    static constexpr double t = 0.01;
    void SetUp() override
    {
        input = perturbed_grid_coverage(30, 30, 1.0, 0.2, 11, 1, 0.004);
        untiled = snap(input, options_at(t));
        const stitch::TiledResult plain = stitch::snap_tiled(input, options_at(t), tiles(stitch::OnError::stop));
        leaves = plain.stitch.leaves;
        for (const stitch::TileReport& tile : plain.tiles) {
            features_of[tile.id] = tile.features;
        }
        ASSERT_GE(leaves, 9u) << "the test needs a tile with neighbours";
        ASSERT_TRUE(differing(plain.result, untiled).empty());
    }
    static stitch::TilingOptions tiles(stitch::OnError on_error)
    {
        stitch::TilingOptions tiling = tiles_of(5.0);
        tiling.on_error = on_error;
        return tiling;
    }
    std::vector<Feature> input;
    SnapResult untiled;
    std::size_t leaves = 0;
    std::map<std::size_t, std::size_t> features_of; ///< features given to each tile (by leaf)
};

TEST_F(OnError, StopThrowsATileErrorNamingTheTileAndTheReason)
{
    const std::size_t leaf = leaves / 2;
    const InjectedFailure fail(std::to_string(leaf));
    try {
        stitch::snap_tiled(input, options_at(t), tiles(stitch::OnError::stop));
        FAIL() << "no error";
    } catch (const stitch::tile_error& e) {
        EXPECT_EQ(e.tile(), leaf);
        const std::string what = e.what();
        EXPECT_NE(what.find("tile " + std::to_string(leaf) + " (core "), std::string::npos) << what;
        EXPECT_NE(what.find("failed: injected failure"), std::string::npos) << what;
    }
}

TEST_F(OnError, SkipRetriesMergedWithItsNeighboursAndLosesNothing)
{
    const InjectedFailure fail(std::to_string(leaves / 2) + "/1"); // fails only alone
    const stitch::TiledResult r = stitch::snap_tiled(input, options_at(t), tiles(stitch::OnError::skip));
    EXPECT_EQ(r.stitch.tiles_failed, 1u);
    EXPECT_EQ(r.stitch.tiles_dropped, 0u);
    EXPECT_EQ(r.stitch.failed_features, 0u);
    EXPECT_LT(r.stitch.tiles, leaves) << "the failed tile was not merged";
    EXPECT_TRUE(differing(r.result, untiled).empty());
    EXPECT_EQ(count_code(r.result, ProblemCode::tile_failed), 0u);
}

TEST_F(OnError, SkipDropsWhatFailsTwiceWholeAndReportsEachFeature)
{
    const InjectedFailure fail(std::to_string(leaves / 2)); // fails alone and merged
    const stitch::TiledResult r = stitch::snap_tiled(input, options_at(t), tiles(stitch::OnError::skip));
    EXPECT_EQ(r.stitch.tiles_failed, 1u);
    EXPECT_EQ(r.stitch.tiles_dropped, 1u);
    std::set<std::int64_t> reported;
    for (const Problem& p : r.result.problems) {
        if (p.code == ProblemCode::tile_failed) {
            EXPECT_TRUE(reported.insert(p.feature_id).second) << "303 twice for " << p.feature_id;
            EXPECT_NE(p.message.find("injected failure"), std::string::npos) << p.message;
        }
    }
    EXPECT_EQ(reported.size(), r.stitch.failed_features);
    // Only the failed tile's own input is lost: the merged retry was split back and its
    // neighbours ran again as they were.
    EXPECT_EQ(reported.size(), features_of.at(leaves / 2));
    ASSERT_GT(reported.size(), 0u);
    const std::map<std::int64_t, std::string> expected = output_by_id(untiled);
    const std::map<std::int64_t, std::string> got = output_by_id(r.result);
    std::size_t kept = 0;
    for (const FeatureOutput& f : r.result.features) {
        if (reported.count(f.id)) {
            EXPECT_TRUE(f.geometry.empty()) << "feature " << f.id << " has 303 but was written";
            continue;
        }
        ++kept;
        EXPECT_EQ(got.at(f.id), expected.at(f.id)) << "feature " << f.id << " differs from the untiled run";
    }
    EXPECT_EQ(kept + reported.size(), input.size());
    // The kept features keep the contract, checked independently (303 excuses the others).
    const ContractReport report = check_contract(checked_features(input), checked_features(r.result),
                                                 reported_problems(r.result), t, engine_rules(options_at(t), 0));
    EXPECT_EQ(report.n_missing, 0u) << report.summary();
    EXPECT_EQ(report.n_invalid, 0u) << report.summary();
    EXPECT_EQ(report.n_overlaps_new, 0u) << report.summary();
    EXPECT_GE(report.min_vertex_vertex, t * (1 - 1e-9)) << report.summary();
}

TEST(OnErrorCancel, SkipNeverSwallowsACancelFromInsideATile)
{
    // One tile of ~32k vertices: the engine calls back several times, so the 6th check (after
    // at most two of the scheduler's) comes from inside the tile. Taken for a tile failure, it
    // would be retried and dropped, and snap() would return.
    const double t = 0.01;
    const auto input = perturbed_grid_coverage(60, 60, 1.0, 0.02, 7, 3, 0.004);
    auto store = tiling::make_memory_store();
    stitch::SpoolMeta meta = spool_features(*store, input, t);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 10000000;
    tiling.threads = 1;
    tiling.on_error = stitch::OnError::skip;
    stitch::ScheduleOptions schedule;
    schedule.threads = 1;
    int checks = 0;
    schedule.check_cancel = [&] {
        if (++checks == 6) {
            throw std::runtime_error("stop");
        }
    };
    stitch::TiledRun run(*store, options_at(t), tiling, schedule);
    run.plan(meta);
    ASSERT_EQ(run.layout().plan.size(), 1u);
    EXPECT_THROW(run.snap(), std::runtime_error);
    EXPECT_EQ(checks, 6);
    EXPECT_EQ(run.missing().size(), 1u);
    EXPECT_EQ(run.stats().tiles_failed, 0u);
}

} // namespace
} // namespace trisnap
