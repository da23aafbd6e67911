// The read and write phases' two stages (src/app/handoff.hpp): the consumer sees the reader's
// sequence whatever the threads; the reader runs ahead by a bounded number of items; what the
// reader made is freed on the reader's thread; an error on either side reaches the caller, the
// reader's after what it read before it was consumed, the consumer's stopping the reader.
#include "app/handoff.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace trisnap {
namespace {

/// Notes the thread that frees it.
struct Freed {
    std::thread::id* where = nullptr;
    ~Freed()
    {
        if (where != nullptr) {
            *where = std::this_thread::get_id();
        }
    }
};

struct Item {
    std::size_t n = 0;
    std::unique_ptr<Freed> payload;
    std::size_t vertices = 1;
    std::size_t weight() const { return vertices; }
};

TEST(Handoff, ConsumerSeesTheReadersSequenceOnOneOrTwoThreads)
{
    for (const bool two : {false, true}) {
        for (const HandoffShape shape : {HandoffShape{}, HandoffShape{1, 1}, HandoffShape{7, 2}}) {
            const std::size_t count = 1000;
            std::size_t next = 0;
            std::vector<std::size_t> seen;
            hand_off<Item>(two, shape,
                           [&](Item& item) {
                               if (next == count) {
                                   return false;
                               }
                               item.n = next++;
                               return true;
                           },
                           [&](Item& item) { seen.push_back(item.n); });
            ASSERT_EQ(seen.size(), count) << "two threads " << two << ", batch " << shape.batch;
            for (std::size_t i = 0; i < count; ++i) {
                ASSERT_EQ(seen[i], i) << "out of order at " << i << ", two threads " << two;
            }
        }
    }
}

// No thread to be had (RLIMIT_NPROC, which does not bind root, so simulated): the loop, on the
// calling thread, with the same sequence.
TEST(Handoff, NoThreadToBeHadIsThePlainLoop)
{
    const std::size_t count = 300;
    std::size_t next = 0;
    std::vector<std::size_t> seen;
    std::size_t starts = 0;
    std::size_t elsewhere = 0;
    const std::thread::id caller = std::this_thread::get_id();
    hand_off<Item>(true, HandoffShape{7, 2},
                   [&](Item& item) {
                       elsewhere += std::this_thread::get_id() != caller ? 1 : 0;
                       if (next == count) {
                           return false;
                       }
                       item.n = next++;
                       return true;
                   },
                   [&](Item& item) {
                       elsewhere += std::this_thread::get_id() != caller ? 1 : 0;
                       seen.push_back(item.n);
                   },
                   [&](auto&&) -> std::thread {
                       ++starts;
                       throw std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again));
                   });
    EXPECT_EQ(starts, 1u);
    EXPECT_EQ(elsewhere, 0u) << "read or consumed on another thread";
    ASSERT_EQ(seen.size(), count);
    for (std::size_t i = 0; i < count; ++i) {
        ASSERT_EQ(seen[i], i) << "out of order at " << i;
    }
}

TEST(Handoff, NothingToReadConsumesNothing)
{
    for (const bool two : {false, true}) {
        std::size_t consumed = 0;
        hand_off<Item>(two, HandoffShape{}, [](Item&) { return false; }, [&](Item&) { ++consumed; });
        EXPECT_EQ(consumed, 0u);
    }
}

/// Hands `count` items of `vertices` each over on two threads, the consumer pausing 1 ms every
/// `pause_every` items so that the reader can fill up; returns the most items read and not yet
/// consumed that the consumer saw.
std::size_t most_ahead(const HandoffShape& shape, std::size_t count, std::size_t vertices, std::size_t pause_every)
{
    std::atomic<std::size_t> read{0};
    std::size_t consumed = 0, ahead = 0;
    hand_off<Item>(true, shape,
                   [&](Item& item) {
                       if (read == count) {
                           return false;
                       }
                       item.n = read++;
                       item.vertices = vertices;
                       return true;
                   },
                   [&](Item&) {
                       ahead = std::max(ahead, read.load() - consumed);
                       ++consumed;
                       if (consumed % pause_every == 0) {
                           std::this_thread::sleep_for(std::chrono::milliseconds(1));
                       }
                   });
    EXPECT_EQ(consumed, count);
    return ahead;
}

TEST(Handoff, ReaderRunsAheadByABoundedNumberOfItems)
{
    const HandoffShape shape{5, 3};
    const std::size_t ahead = most_ahead(shape, 2000, 1, 100);
    // tokens full batches queued, the one being consumed, the one being filled.
    EXPECT_LE(ahead, shape.batch * (shape.tokens + 2));
    EXPECT_GE(ahead, shape.batch * shape.tokens) << "the reader never got ahead: not two threads?";
}

TEST(Handoff, HeavyItemsMakeSmallBatches)
{
    // Features of 300 vertices, batches closed at 1000 vertices: 4 features a batch, however
    // many the count allows, so the memory in flight follows the vertices.
    const HandoffShape shape{64, 2, 1000};
    EXPECT_LE(most_ahead(shape, 500, 300, 20), 4 * (shape.tokens + 2)) << "batches were not closed by weight";
}

TEST(Handoff, WhatTheReaderMadeIsFreedOnItsThread)
{
    const std::size_t count = 64 * 20;
    std::vector<std::thread::id> freed_on(count);
    std::thread::id reader;
    std::size_t next = 0;
    hand_off<Item>(true, HandoffShape{64, 4},
                   [&](Item& item) {
                       reader = std::this_thread::get_id();
                       if (next == count) {
                           return false;
                       }
                       item.n = next;
                       item.payload = std::make_unique<Freed>(Freed{&freed_on[next]});
                       ++next;
                       return true;
                   },
                   [&](Item&) {});
    ASSERT_NE(reader, std::this_thread::get_id()) << "the reader had no thread of its own";
    // The batches still in flight when the reader ended are freed by the caller: at most the
    // tokens' worth (plus the last, partial batch).
    std::size_t on_reader = 0;
    for (const std::thread::id& id : freed_on) {
        on_reader += id == reader ? 1 : 0;
    }
    EXPECT_GE(on_reader, count - 64 * 5) << "items were freed on the consumer's thread";
}

TEST(Handoff, ReadersErrorComesAfterWhatItReadBefore)
{
    for (const bool two : {false, true}) {
        std::size_t next = 0;
        std::vector<std::size_t> seen;
        EXPECT_THROW(hand_off<Item>(two, HandoffShape{8, 2},
                                    [&](Item& item) {
                                        if (next == 100) {
                                            throw std::runtime_error("damaged");
                                        }
                                        item.n = next++;
                                        return true;
                                    },
                                    [&](Item& item) { seen.push_back(item.n); }),
                     std::runtime_error);
        EXPECT_EQ(seen.size(), 100u) << "two threads " << two << ": every item read before the error is consumed";
    }
}

TEST(Handoff, ConsumersErrorStopsTheReader)
{
    std::atomic<std::size_t> read{0};
    EXPECT_THROW(hand_off<Item>(true, HandoffShape{4, 2},
                                [&](Item& item) {
                                    item.n = read++;
                                    return true; // endless: only the consumer's error ends it
                                },
                                [&](Item& item) {
                                    if (item.n == 50) {
                                        throw std::logic_error("write failed");
                                    }
                                }),
                 std::logic_error);
    EXPECT_LE(read.load(), 50u + 4 * 4) << "the reader went on after the consumer failed";
}

} // namespace
} // namespace trisnap
