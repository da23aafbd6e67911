// The write phase's feed: the stitched features in the source's order, with or without the
// producer thread, within its byte bound, errors thrown at their place, and a consumer that
// leaves early never leaves the producer running.
#include "app/merger_feed.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

namespace trisnap {
namespace {

// Feature i has a line of (i % 7) + 2 points; the source ends after `count` features and
// throws instead of giving feature `throw_at`.
struct CountingSource {
    std::size_t count = 0;
    std::size_t throw_at = SIZE_MAX;
    std::atomic<std::size_t> calls{0};

    bool operator()(stitch::OutputItem& item)
    {
        const std::size_t i = calls++;
        if (i == throw_at) {
            throw std::runtime_error("damaged work file at " + std::to_string(i));
        }
        if (i >= count) {
            return false;
        }
        item = stitch::OutputItem{};
        item.seq = i;
        item.output.geometry.type = Geometry::Type::LineString;
        item.output.geometry.lines.emplace_back(i % 7 + 2, Coord{static_cast<double>(i), 0.0, 0.0});
        return true;
    }
};

MergerFeed::Source source_of(CountingSource& s)
{
    return [&s](stitch::OutputItem& item) { return s(item); };
}

TEST(MergerFeed, GivesEveryFeatureInOrderWithOrWithoutTheThread)
{
    for (int threads : {1, 2, 8}) {
        CountingSource s;
        s.count = 1000;
        const std::uint64_t bound = 3 * 8 * sizeof(Coord); // about three features
        MergerFeed feed(source_of(s), threads, bound);
        stitch::OutputItem item;
        std::size_t n = 0;
        while (feed.next(item)) {
            ASSERT_EQ(item.seq, n) << threads << " threads";
            ASSERT_EQ(item.output.geometry.lines.at(0).size(), n % 7 + 2);
            EXPECT_EQ(item.output.geometry.lines[0][0].x, static_cast<double>(n));
            ++n;
        }
        EXPECT_EQ(n, 1000u) << threads << " threads";
        EXPECT_FALSE(feed.next(item)) << "the end stays the end";
        EXPECT_LE(feed.peak_bytes(), bound) << threads << " threads";
        if (threads == 1) {
            EXPECT_EQ(feed.peak_bytes(), 0u) << "one thread: nothing is queued";
        } else {
            EXPECT_GT(feed.peak_bytes(), 0u) << "the producer queued features ahead";
        }
    }
}

TEST(MergerFeed, QueuesAFeatureLargerThanTheBoundAlone)
{
    CountingSource s;
    s.count = 50;
    MergerFeed feed(source_of(s), 2, 1); // every feature is larger than 1 byte
    stitch::OutputItem item;
    std::size_t n = 0;
    while (feed.next(item)) {
        ASSERT_EQ(item.seq, n++);
    }
    EXPECT_EQ(n, 50u);
    EXPECT_LE(feed.peak_bytes(), 8 * sizeof(Coord)) << "one feature at a time";
}

TEST(MergerFeed, ThrowsTheSourcesErrorAtItsPlace)
{
    for (int threads : {1, 2}) {
        CountingSource s;
        s.count = 100;
        s.throw_at = 5;
        MergerFeed feed(source_of(s), threads, 1 << 20);
        stitch::OutputItem item;
        for (std::size_t i = 0; i < 5; ++i) {
            ASSERT_TRUE(feed.next(item));
            EXPECT_EQ(item.seq, i);
        }
        try {
            feed.next(item);
            FAIL() << "the source's error was lost (" << threads << " threads)";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "damaged work file at 5");
        }
    }
}

TEST(MergerFeed, AConsumerThatLeavesEarlyStopsTheProducer)
{
    CountingSource s;
    s.count = 1'000'000;
    {
        MergerFeed feed(source_of(s), 2, 4 * 8 * sizeof(Coord));
        stitch::OutputItem item;
        ASSERT_TRUE(feed.next(item));
        ASSERT_TRUE(feed.next(item));
        feed.stop();
        const std::size_t after_stop = s.calls;
        // What was queued is still given, then the end; the source is not called again.
        while (feed.next(item)) {
        }
        EXPECT_EQ(s.calls.load(), after_stop);
        EXPECT_LT(after_stop, 20u) << "the bound held the producer back";
    } // the destructor after stop() joins nothing more and does not hang
    CountingSource t;
    t.count = 1'000'000;
    {
        MergerFeed feed(source_of(t), 2, 1 << 10);
        stitch::OutputItem item;
        ASSERT_TRUE(feed.next(item)); // then the consumer throws, say: only the destructor runs
    }
    EXPECT_LT(t.calls.load(), 1000u);
}

} // namespace
} // namespace trisnap
