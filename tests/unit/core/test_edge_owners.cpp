// The owner table (src/core/edge_owners.hpp) against a plain std::map doing the same edits:
// adds, takes, renames, in tables sized ahead (reserve) and grown from empty, small enough that
// probe runs wrap past the table's end and deletions shift keys back across it. The engine's
// outputs do not show a lost or misplaced entry when it happens to land on an edge nothing reads
// again; this does.
#include "core/edge_owners.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace trisnap {
namespace {

using detail::EdgeOwners;
using detail::OwnerRef;

/// Entries keyed by (low id, high id), oriented low -> high, in the order they were added.
using Reference = std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<OwnerRef>>;

std::pair<std::uint32_t, std::uint32_t> edge_key(std::uint32_t a, std::uint32_t b)
{
    return {std::min(a, b), std::max(a, b)};
}

OwnerRef oriented(OwnerRef r, bool flip)
{
    r.forward = r.forward != flip;
    return r;
}

bool same(const std::vector<OwnerRef>& a, const std::vector<OwnerRef>& b)
{
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const OwnerRef& x, const OwnerRef& y) {
        return x.owner == y.owner && x.forward == y.forward;
    });
}

/// Every edge of the reference is found with its entries in both directions, the table holds
/// no other edge, and it is at most 70 % full.
void expect_equal(const EdgeOwners& table, const Reference& ref)
{
    ASSERT_EQ(table.edges(), ref.size());
    EXPECT_LE(10 * table.edges(), 7 * table.slots());
    std::vector<OwnerRef> got;
    for (const auto& [k, entries] : ref) {
        got.clear();
        table.get(k.first, k.second, got);
        EXPECT_TRUE(same(got, entries)) << k.first << "-" << k.second;
        got.clear();
        table.get(k.second, k.first, got);
        std::vector<OwnerRef> back;
        for (const OwnerRef& r : entries) back.push_back(oriented(r, true));
        EXPECT_TRUE(same(got, back)) << k.second << "-" << k.first;
        EXPECT_TRUE(table.contains(k.second, k.first));
    }
    std::size_t seen = 0;
    std::vector<OwnerRef> buffer;
    table.for_each_grouped(
        [&](std::uint32_t u, std::uint32_t v, std::span<const OwnerRef> refs) {
            ++seen;
            EXPECT_LT(u, v);
            const auto it = ref.find({u, v});
            ASSERT_NE(it, ref.end()) << u << "-" << v << " is not an edge";
            EXPECT_TRUE(same(std::vector<OwnerRef>(refs.begin(), refs.end()), it->second));
        },
        buffer);
    EXPECT_EQ(seen, ref.size());
}

/// Random edits on `vertices` vertex ids: mostly adds (some to edges that exist: a second
/// owner), takes of existing and of absent edges, and now and then a renaming of ids.
void run_edits(EdgeOwners& table, std::uint32_t vertices, int steps, std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::uint32_t> id(0, vertices - 1);
    Reference ref;
    std::uint32_t owner = 0;
    for (int step = 0; step < steps; ++step) {
        const std::uint64_t what = rng() % 100;
        const std::uint32_t a = id(rng);
        std::uint32_t b = id(rng);
        if (a == b) {
            b = (b + 1) % vertices;
        }
        if (what < 60) {
            const OwnerRef r{owner++, (rng() & 1) != 0};
            const bool created = table.add(a, b, r);
            std::vector<OwnerRef>& entries = ref[edge_key(a, b)];
            EXPECT_EQ(created, entries.empty());
            entries.push_back(oriented(r, a > b));
        } else if (what < 95) {
            // Take an edge that exists, when there is one near a random key.
            auto it = ref.lower_bound(edge_key(a, b));
            if (it == ref.end()) {
                it = ref.begin();
            }
            if (it == ref.end()) {
                continue;
            }
            const auto [u, v] = it->first;
            const bool flip = (rng() & 1) != 0;
            std::vector<OwnerRef> got;
            table.take(flip ? v : u, flip ? u : v, got);
            std::vector<OwnerRef> want;
            for (const OwnerRef& r : it->second) want.push_back(oriented(r, flip));
            EXPECT_TRUE(same(got, want));
            ref.erase(it);
            EXPECT_FALSE(table.contains(u, v));
        } else if (what < 99) {
            std::vector<OwnerRef> got;
            if (ref.count(edge_key(a, b)) == 0) {
                table.take(a, b, got); // absent: nothing happens
                EXPECT_TRUE(got.empty());
            }
        } else {
            // A permutation of every id, or of the upper half only (the engine renames the
            // crossing vertices, numbered after the input points): edges between kept ids,
            // between a kept and a renamed id, and between renamed ids.
            std::vector<std::uint32_t> rename(vertices);
            for (std::uint32_t i = 0; i < vertices; ++i) rename[i] = i;
            const std::uint32_t first = (rng() & 1) != 0 ? 0 : vertices / 2;
            std::shuffle(rename.begin() + first, rename.end(), rng);
            table.rename(rename);
            Reference renamed;
            for (const auto& [k, entries] : ref) {
                const std::uint32_t u = rename[k.first];
                const std::uint32_t v = rename[k.second];
                std::vector<OwnerRef>& into = renamed[edge_key(u, v)];
                for (const OwnerRef& r : entries) into.push_back(oriented(r, u > v));
            }
            ref.swap(renamed);
        }
        if (step % 97 == 0) {
            expect_equal(table, ref);
            if (testing::Test::HasFailure()) {
                return;
            }
        }
    }
    expect_equal(table, ref);
}

TEST(EdgeOwners, GrownFromEmptyMatchesAMap)
{
    EdgeOwners table;
    run_edits(table, 60, 4000, 1); // ~1,700 possible edges: many probe runs wrap
    EXPECT_GT(table.slots(), 64u) << "the case must make the table grow";
}

TEST(EdgeOwners, SizedAheadMatchesAMap)
{
    for (const std::uint64_t seed : {2, 3, 4}) {
        EdgeOwners table;
        table.reserve(300, 300);
        run_edits(table, 40, 3000, seed);
    }
}

TEST(EdgeOwners, ManyVerticesFewCollisionsMatchesAMap)
{
    EdgeOwners table;
    table.reserve(5000, 5000);
    run_edits(table, 100000, 20000, 5);
}

// Sized for n edges, the table takes n without growing, and is then between half and 70 %
// full; one grown from empty is at most 70 % full after each growth by half.
TEST(EdgeOwners, ReserveHoldsWhatItWasSizedFor)
{
    for (const std::size_t n : {1u, 63u, 64u, 1000u, 123457u}) {
        EdgeOwners table;
        table.reserve(n, n);
        const std::size_t slots = table.slots();
        for (std::uint32_t i = 0; i < n; ++i) {
            table.add(i, i + 1, OwnerRef{i, true});
        }
        EXPECT_EQ(table.slots(), slots) << n << " edges";
        EXPECT_LE(10 * n, 7 * slots);
        if (n >= 1000) {
            EXPECT_GE(2 * n, slots) << "sized for " << n << " edges: not more than twice their number";
        }
    }
}

} // namespace
} // namespace trisnap
