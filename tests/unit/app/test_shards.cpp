// Shares of a cluster run: the assignment is deterministic, complete and balanced, ties go the
// documented way; the task index and count come from the flags, then the array variables in
// their order, and a bad index is refused naming where it came from.
#include "app/shards.hpp"
#include "config/errors.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

namespace trisnap {
namespace {

std::vector<ShardTile> random_tiles(std::size_t n, unsigned seed)
{
    std::mt19937 random(seed);
    std::uniform_int_distribution<std::uint64_t> vertices(1, 100000);
    std::vector<ShardTile> tiles;
    for (std::size_t k = 0; k < n; ++k) {
        tiles.push_back(ShardTile{k * 3 + 1, vertices(random)});
    }
    return tiles;
}

TEST(Shards, EveryTileOnceAndNoShardHeavierThanTheLightestPlusOneTile)
{
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const std::vector<ShardTile> tiles = random_tiles(300 + seed * 7, seed);
        for (std::size_t shards : {1u, 2u, 7u, 64u}) {
            const std::vector<std::size_t> owner = assign_shards(tiles, shards);
            ASSERT_EQ(owner.size(), tiles.size());
            EXPECT_TRUE(std::all_of(owner.begin(), owner.end(), [&](std::size_t s) { return s < shards; }));
            const std::vector<std::uint64_t> loads = shard_loads(tiles, owner, shards);
            std::uint64_t largest = 0;
            for (const ShardTile& t : tiles) {
                largest = std::max(largest, t.vertices);
            }
            const auto [least, most] = std::minmax_element(loads.begin(), loads.end());
            EXPECT_LE(*most - *least, largest) << "seed " << seed << ", " << shards << " shards";
        }
    }
}

TEST(Shards, TheAssignmentDependsOnlyOnTheTilesNotTheirOrder)
{
    std::vector<ShardTile> tiles = random_tiles(500, 7);
    const std::vector<std::size_t> owner = assign_shards(tiles, 9);
    std::map<std::size_t, std::size_t> by_id;
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        by_id[tiles[k].id] = owner[k];
    }
    std::shuffle(tiles.begin(), tiles.end(), std::mt19937(3));
    const std::vector<std::size_t> again = assign_shards(tiles, 9);
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        EXPECT_EQ(again[k], by_id[tiles[k].id]) << "tile " << tiles[k].id;
    }
}

TEST(Shards, LargestFirstTiesByIdEachToTheLeastLoadedLowestShard)
{
    // Sorted: 90 (id 4), 50 (id 2), 50 (id 8), 10 (id 1), 10 (id 6), 10 (id 7).
    const std::vector<ShardTile> tiles{{8, 50}, {1, 10}, {4, 90}, {2, 50}, {7, 10}, {6, 10}};
    const std::vector<std::size_t> owner = assign_shards(tiles, 2);
    // 90 -> 0; 50 (id 2) -> 1; 50 (id 8) -> 1 (50 < 90); then 10s: 0 has 90, 1 has 100.
    const std::map<std::size_t, std::size_t> expected{{4, 0}, {2, 1}, {8, 1}, {1, 0}, {6, 0}, {7, 1}};
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        EXPECT_EQ(owner[k], expected.at(tiles[k].id)) << "tile " << tiles[k].id;
    }
}

TEST(Shards, SuggestionKeepsTasksBigAndArraysUnderTheCap)
{
    EXPECT_EQ(suggest_shards({}), 1u);
    EXPECT_EQ(suggest_shards(random_tiles(10, 1)), 1u); // fewer than 16 tiles
    std::vector<ShardTile> many(100000, ShardTile{0, 1000000});
    EXPECT_EQ(suggest_shards(many), k_max_shards);
    std::vector<ShardTile> small(3200, ShardTile{0, 100}); // 200 shards by tiles, 0 by vertices
    EXPECT_EQ(suggest_shards(small), 1u);
    std::vector<ShardTile> even(1600, ShardTile{0, 100000}); // 100 by tiles, 32 by vertices
    EXPECT_EQ(suggest_shards(even), 32u);
}

EnvLookup env_of(std::map<std::string, std::string> vars)
{
    return [vars = std::move(vars)](const char* name) -> const char* {
        const auto it = vars.find(name);
        return it == vars.end() ? nullptr : it->second.c_str();
    };
}

TEST(Shards, IndexFromFlagsThenSlurmThenKubernetesThenAwsBatch)
{
    const auto all = env_of({{"SLURM_ARRAY_TASK_ID", "12"}, {"SLURM_ARRAY_TASK_MIN", "10"}, {"SLURM_ARRAY_TASK_COUNT", "5"},
                             {"JOB_COMPLETION_INDEX", "3"}, {"AWS_BATCH_JOB_ARRAY_INDEX", "4"}});
    ShardIndex s = resolve_shard(1, 6, 0, all);
    EXPECT_EQ(s.index, 1u);
    EXPECT_EQ(s.count, 6u);
    EXPECT_EQ(s.source, "--shard");
    s = resolve_shard(std::nullopt, std::nullopt, 0, all);
    EXPECT_EQ(s.index, 2u);
    EXPECT_EQ(s.count, 5u);
    EXPECT_EQ(s.source, "SLURM_ARRAY_TASK_ID");
    s = resolve_shard(std::nullopt, std::nullopt, 8, env_of({{"JOB_COMPLETION_INDEX", "3"}, {"AWS_BATCH_JOB_ARRAY_INDEX", "4"}}));
    EXPECT_EQ(s.index, 3u);
    EXPECT_EQ(s.count, 8u); // the plan's
    EXPECT_EQ(s.source, "JOB_COMPLETION_INDEX");
    s = resolve_shard(std::nullopt, 5, 8, env_of({{"AWS_BATCH_JOB_ARRAY_INDEX", "4"}}));
    EXPECT_EQ(s.index, 4u);
    EXPECT_EQ(s.count, 5u);
}

void expect_refused(std::optional<long long> shard, std::optional<long long> count, std::size_t recorded,
                    const EnvLookup& env, const std::string& text)
{
    try {
        resolve_shard(shard, count, recorded, env);
        ADD_FAILURE() << "accepted; expected: " << text;
    } catch (const argument_error& e) {
        EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
}

TEST(Shards, BadIndexOrCountIsRefusedNamingItsSource)
{
    const auto none = env_of({});
    expect_refused(std::nullopt, 4, 0, none, "no shard index: give --shard I");
    expect_refused(0, std::nullopt, 0, none, "no number of shards: give --num-shards N");
    expect_refused(4, 4, 0, none, "shard 4 from --shard is outside 0..3 (4 shards from --num-shards)");
    expect_refused(-1, 4, 0, none, "shard -1 from --shard is outside 0..3");
    expect_refused(0, 0, 0, none, "--num-shards 0: the number of shards must be >= 1");
    expect_refused(std::nullopt, std::nullopt, 0, env_of({{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_COUNT", "3"}}),
                   "shard 3 from SLURM_ARRAY_TASK_ID (less SLURM_ARRAY_TASK_MIN) is outside 0..2");
    expect_refused(std::nullopt, std::nullopt, 2, env_of({{"SLURM_ARRAY_TASK_ID", "1x"}}),
                   "SLURM_ARRAY_TASK_ID='1x' is not a task index");
    expect_refused(std::nullopt, std::nullopt, 2, env_of({{"JOB_COMPLETION_INDEX", "-2"}}),
                   "JOB_COMPLETION_INDEX='-2' is not a task index");
}

} // namespace
} // namespace trisnap
