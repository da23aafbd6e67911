// How large the tiles may be under a memory pool (stitch::pool_tile_vertices): a thread's share
// of the pool while that share holds a useful tile, else fewer tiles at once and larger ones,
// never the 16-vertex tiles a share below the model's fixed part per tile gave (Andorra x43
// under 155 MiB: minutes instead of seconds).
#include "stitch/tiled_snap.hpp"

#include <gtest/gtest.h>

namespace trisnap {
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;

TEST(PoolTiles, AShareOfThePoolWhileItHoldsAUsefulTileElseTheWholePool)
{
    const stitch::MemoryModel model; // 8 MiB a tile, 1,100 bytes a vertex
    const std::uint64_t wanted = 50000;
    // No pool: the budget asked for; a pool for two full tiles: the same.
    EXPECT_EQ(stitch::pool_tile_vertices(model, 0, 2, wanted), wanted);
    EXPECT_EQ(stitch::pool_tile_vertices(model, 2 * model.tile_bytes(wanted), 2, wanted), wanted);
    // Room for two tiles of 20,000: each thread's share.
    const std::uint64_t two_of_20k = 2 * model.tile_bytes(20000);
    EXPECT_EQ(stitch::pool_tile_vertices(model, two_of_20k, 2, wanted), model.vertices_within(two_of_20k / 2));
    EXPECT_GE(stitch::pool_tile_vertices(model, two_of_20k, 2, wanted), 19999u);
    // 15 MiB and 9 MiB: half is below the model's fixed 8 MiB a tile (the old rule's 16-vertex
    // tiles), so one tile at a time with all of it: ~6,600 and ~950 vertices.
    EXPECT_EQ(stitch::pool_tile_vertices(model, 15 * k_mib, 2, wanted), model.vertices_within(15 * k_mib));
    EXPECT_GT(stitch::pool_tile_vertices(model, 15 * k_mib, 2, wanted), 6500u);
    EXPECT_EQ(stitch::pool_tile_vertices(model, 9 * k_mib, 2, wanted), model.vertices_within(9 * k_mib));
    EXPECT_GT(stitch::pool_tile_vertices(model, 9 * k_mib, 2, wanted), 900u);
    // Eight threads: the most threads whose share still holds a useful tile.
    const std::uint64_t four_of_12k = 4 * model.tile_bytes(12000);
    EXPECT_EQ(stitch::pool_tile_vertices(model, four_of_12k, 8, wanted), model.vertices_within(four_of_12k / 4));
    // A budget below the useful size is kept when a share holds it.
    EXPECT_EQ(stitch::pool_tile_vertices(model, 2 * model.tile_bytes(3000), 2, 3000), 3000u);
    // A pool below one tile's fixed part: the floor of 16 (memory_pool() refuses such a run first).
    EXPECT_EQ(stitch::pool_tile_vertices(model, 4 * k_mib, 2, wanted), 16u);
}

} // namespace
} // namespace trisnap
