// The smallest memory limit a run would work under is a fixed point: the margin kept beside the
// tiles (a quarter of the limit) and the read's buffers (a sample and FIDs, each a sixteenth of
// the limit, up to what the layer fills) grow with the limit, so the limit that
// would have been enough with the margin of the limit tried is not enough for a fresh run.
#include "app/budget.hpp"

#include <gtest/gtest.h>

namespace trisnap {
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;

// What a fresh run under `limit` needs: the process without its limit-sized buffers, those
// buffers at `limit`, the margin at `limit`, the tile.
std::uint64_t need(std::uint64_t fixed, const HeldByLimit& grows, std::uint64_t limit, std::uint64_t tile)
{
    return fixed + grows.at(limit) + reserved_margin(limit) + tile;
}

TEST(SmallestLimit, IsTheLeastLimitThatHoldsWhatItsOwnMarginAndBuffersAdd)
{
    const std::uint64_t tile = 29 * k_mib;
    const std::uint64_t tried = 32 * k_mib;
    struct Case {
        const char* name;
        HeldByLimit grows;
    };
    for (const Case& c : {Case{"nothing grows", HeldByLimit{}},
                          Case{"a small layer (its buffers are full at any limit)", HeldByLimit{10000, 1000}},
                          Case{"a large layer (its buffers grow with the limit)", HeldByLimit{1u << 30, 1u << 28}}}) {
        SCOPED_TRACE(c.name);
        const std::uint64_t held = 62 * k_mib + c.grows.at(tried);
        const std::uint64_t fixed = held - c.grows.at(tried);
        const std::uint64_t limit = smallest_limit(tried, held, c.grows, tile);
        EXPECT_EQ(limit % k_mib, 0u);
        EXPECT_GE(limit, need(fixed, c.grows, limit, tile)) << "a fresh run at the suggestion does not fit";
        EXPECT_LT(limit - k_mib, need(fixed, c.grows, limit - k_mib, tile)) << "a MiB less would fit too";
        // What the earlier suggestion said: enough only with the margin of the limit tried.
        const std::uint64_t naive = held + reserved_margin(tried) + tile;
        EXPECT_LT(naive, need(fixed, c.grows, naive, tile));
        EXPECT_GT(limit, naive);
    }
}

TEST(SmallestLimit, WithNothingGrowingIsFourThirdsOfWhatIsFixed)
{
    const std::uint64_t fixed = 62 * k_mib + 16 * k_mib + 29 * k_mib; // process, margin's constant, tile
    const std::uint64_t limit = smallest_limit(32 * k_mib, 62 * k_mib, HeldByLimit{}, 29 * k_mib);
    EXPECT_EQ(limit, (fixed * 4 / 3 + k_mib - 1) / k_mib * k_mib);
}

} // namespace
} // namespace trisnap
