// The snapper's queue (src/core/snapper_impl.hpp): its pops against a sort of the same events,
// and the face candidates' keys rounded up to floats.
// The engine's output depends on the order events come out in: a heap that popped a larger
// event first, or that lost or repeated one, would change which edits happen; the byte
// identity of the shared-layer runs would show it only on layers that happen to need it.
#include "core/snapper_impl.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace trisnap {
namespace {

using detail::Event;
using detail::EventQueue;
using detail::Kind;

// Random events with many equal distances and some pushed twice, pushed and popped in bursts
// as the snapper does (a pop, then a few pushes from the edit): every pop is the smallest event
// queued at that moment (a std::multiset kept beside the queue says which), and the queue
// drains to exactly what was pushed.
TEST(EventQueue, EveryPopIsTheSmallestQueued) {
    std::mt19937_64 rng(11);
    std::uniform_int_distribution<int> small(0, 7);
    std::uniform_int_distribution<std::uint32_t> id(0, 40);
    const Kind kinds[4] = {Kind::face, Kind::merge, Kind::sliver, Kind::edge};
    for (const int burst : {1, 3, 9}) {
        EventQueue queue;
        std::multiset<Event> mirror;
        Event last{};
        std::size_t pops = 0;
        const auto pop = [&] {
            ASSERT_FALSE(mirror.empty());
            const Event top = queue.top();
            const Event& smallest = *mirror.begin();
            ASSERT_TRUE(!(top < smallest) && !(smallest < top)) << "burst " << burst << ", pop " << pops;
            mirror.erase(mirror.begin());
            queue.pop();
            ++pops;
        };
        for (int round = 0; round < 4000; ++round) {
            for (int k = small(rng) % burst; k >= 0; --k) {
                const Event e = small(rng) == 0
                                    ? last
                                    : Event{0.125 * small(rng), kinds[small(rng) % 4], id(rng), id(rng), id(rng)};
                queue.push(e);
                mirror.insert(e);
                last = e;
            }
            if (small(rng) < 4) {
                pop();
            }
            ASSERT_EQ(queue.size(), mirror.size());
        }
        while (!queue.empty()) {
            pop();
        }
        EXPECT_TRUE(mirror.empty()) << "burst " << burst;
    }
}

// The face candidates' keys: the smallest float not below the distance, so a face is taken as
// covered only by a candidate whose distance is truly smaller (Snapper::check_face); beyond the
// float range, no key (every face queued).
TEST(EventQueue, FaceKeysRoundUp) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> mantissa(1.0, 2.0);
    std::uniform_int_distribution<int> exponent(-140, 120);
    for (int i = 0; i < 100000; ++i) {
        const double d2 = std::ldexp(mantissa(rng), exponent(rng));
        const float key = detail::rounded_up(d2);
        ASSERT_GE(double{key}, d2) << d2;
        ASSERT_LT(double{std::nextafter(key, 0.0f)}, d2) << d2;
    }
    EXPECT_EQ(detail::rounded_up(0.0), 0.0f);
    EXPECT_EQ(detail::rounded_up(0.25), 0.25f);
    EXPECT_EQ(detail::rounded_up(1e300), detail::k_no_face);
    EXPECT_EQ(detail::rounded_up(std::numeric_limits<double>::infinity()), detail::k_no_face);
}

} // namespace
} // namespace trisnap
