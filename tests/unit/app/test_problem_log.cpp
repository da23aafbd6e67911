// The problem log: many problems through a tiny buffer come back in exactly the order a stable
// sort of them all gives, with the counts, while at most the buffer is held in memory; a log
// saved and loaded by another process continues with its runs; the report's problem list,
// streamed one problem at a time, is byte for byte what dumping the whole document gives.
#include "app/problem_log.hpp"
#include "app/report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace trisnap {
namespace {

std::vector<Problem> random_problems(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::vector<Problem> out;
    const ProblemCode codes[] = {ProblemCode::repeated_points, ProblemCode::self_intersection,
                                 ProblemCode::collapsed_polygon, ProblemCode::seam_mismatch};
    for (std::size_t i = 0; i < n; ++i) {
        Problem p;
        p.feature_id = static_cast<std::int64_t>(rng() % 50) - 5; // many ties, negative FIDs
        p.code = codes[rng() % 4];
        p.layer = rng() % 3;
        p.message = "problem " + std::to_string(i); // tells ties apart
        p.x = i % 7 == 0 ? std::nan("") : static_cast<double>(i);
        p.y = -static_cast<double>(i);
        out.push_back(p);
    }
    return out;
}

std::vector<Problem> read_back(const ProblemLog& log)
{
    std::vector<Problem> out;
    log.for_each([&](const Problem& p) { out.push_back(p); });
    return out;
}

void expect_same(const std::vector<Problem>& a, const std::vector<Problem>& b)
{
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].layer, b[i].layer) << i;
        EXPECT_EQ(a[i].feature_id, b[i].feature_id) << i;
        EXPECT_EQ(a[i].code, b[i].code) << i;
        ASSERT_EQ(a[i].message, b[i].message) << i;
        EXPECT_EQ(std::isnan(a[i].x), std::isnan(b[i].x)) << i;
    }
}

TEST(ProblemLog, ManyProblemsThroughATinyBufferComeBackStablySorted)
{
    auto store = tiling::make_memory_store();
    const std::size_t buffer = 4096; // a few dozen problems
    ProblemLog log(*store, "problems-read-", buffer);
    std::vector<Problem> all = random_problems(6000, 1);
    std::size_t largest = 0;
    for (std::size_t i = 0; i < 3000; ++i) {
        log.add(all[i]);
        largest = std::max(largest, log.buffered_bytes());
    }
    log.begin_phase("problems-write-"); // a second phase, as the write's after the read's
    for (std::size_t i = 3000; i < all.size(); ++i) {
        log.add(all[i]);
        largest = std::max(largest, log.buffered_bytes());
    }
    EXPECT_LE(largest, buffer + sizeof(Problem) + 32) << "the buffer grew past its bound";
    EXPECT_LE(log.runs().size(), 2 * ProblemLog::k_max_runs) << "runs were not merged";
    EXPECT_GT(log.runs().size(), 1u);
    std::stable_sort(all.begin(), all.end(), problem_order);
    expect_same(all, read_back(log)); // with part of the write phase still buffered
    log.seal();
    expect_same(all, read_back(log));
    EXPECT_EQ(log.size(), all.size());
    std::uint64_t layer1 = 0;
    std::map<int, std::uint64_t> codes;
    for (const Problem& p : all) {
        layer1 += p.layer == 1 ? 1 : 0;
        ++codes[static_cast<int>(p.code)];
    }
    EXPECT_EQ(log.in_layer(1), layer1);
    EXPECT_EQ(log.by_code(), codes);
}

TEST(ProblemLog, ASavedLogContinuesInAnotherProcessAndAStoppedPhaseStartsOver)
{
    auto store = tiling::make_memory_store();
    std::vector<Problem> all = random_problems(500, 2);
    std::string saved;
    {
        ProblemLog read(*store, "problems-read-", 1000);
        for (std::size_t i = 0; i < 300; ++i) {
            read.add(all[i]);
        }
        read.seal();
        tiling::ByteWriter w(saved);
        read.save(w);
        ProblemLog stopped = read; // a write phase that stops half way leaves runs behind
        stopped.begin_phase("problems-write-");
        for (std::size_t i = 0; i < 400; ++i) {
            stopped.add(all[i]);
        }
    }
    ASSERT_TRUE(store->exists("problems-write-0"));
    ProblemLog log(*store, "problems-read-", 1000);
    tiling::ByteReader r(saved, "test");
    log.load(r);
    log.begin_phase("problems-write-");
    for (std::size_t i = 300; i < all.size(); ++i) {
        log.add(all[i]);
    }
    log.seal();
    std::stable_sort(all.begin(), all.end(), problem_order);
    expect_same(all, read_back(log));
}

TEST(ProblemLog, WithoutAStoreEverythingStaysInMemory)
{
    ProblemLog log;
    std::vector<Problem> all = random_problems(100, 3);
    for (const Problem& p : all) {
        log.add(p);
    }
    log.seal();
    EXPECT_TRUE(log.runs().empty());
    std::stable_sort(all.begin(), all.end(), problem_order);
    expect_same(all, read_back(log));
    log.close();
    EXPECT_EQ(log.size(), 100u);
    EXPECT_THROW(read_back(log), std::logic_error);
}

// The report's last member streamed: the same bytes as dumping it whole, for no item, one, many,
// with text that is not valid UTF-8, escapes and nulls.
TEST(ReportStream, StreamedArrayGivesTheBytesOfTheWholeDump)
{
    using nlohmann::ordered_json;
    for (std::size_t n : {0u, 1u, 5u}) {
        ordered_json document = {{"tool", "trisnap"}, {"counts", {{"problems", n}, {"nested", {1, 2}}}}};
        ordered_json items = ordered_json::array();
        for (std::size_t i = 0; i < n; ++i) {
            items.push_back({{"fid", i}, {"message", std::string("bad \xff byte, \"quote\"\nnewline")},
                             {"x", i % 2 ? ordered_json(nullptr) : ordered_json(1.5)}, {"list", {1, {{"a", 2}}}}});
        }
        ordered_json whole = document;
        whole["problems"] = items;
        const std::string expected = whole.dump(2, ' ', false, ordered_json::error_handler_t::replace);
        document["problems"] = ordered_json::array();
        std::string streamed;
        write_json_streaming_last_array(
            document, "problems",
            [&](const auto& put) {
                for (const ordered_json& item : items) {
                    put(item);
                }
            },
            [&](std::string_view piece) { streamed.append(piece); });
        EXPECT_EQ(streamed, expected) << n << " items";
    }
    ordered_json not_last = {{"problems", ordered_json::array()}, {"after", 1}};
    EXPECT_THROW(write_json_streaming_last_array(not_last, "problems", [](const auto&) {}, [](std::string_view) {}),
                 std::logic_error);
}

} // namespace
} // namespace trisnap
