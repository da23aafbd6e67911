// ExternalSorter (io/external_sort.hpp): records in runs on disk read back in the order one
// std::sort of them all gives, whatever the capacity (one run, many, more than one merge can
// open at once); nothing on disk while they fit; the files gone afterwards; a directory that
// cannot be made is a failure named to the caller.
#include "io/external_sort.hpp"

#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <random>
#include <stdexcept>
#include <vector>

namespace trisnap {
namespace {

struct Row {
    std::int64_t key = 0;
    double payload = 0;
};
struct ByKey {
    bool operator()(const Row& a, const Row& b) const { return a.key < b.key; }
};

std::size_t files_in(const std::filesystem::path& dir)
{
    if (!std::filesystem::exists(dir)) {
        return 0;
    }
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

TEST(ExternalSorter, ReadsBackInOrderWhateverTheCapacity)
{
    const std::size_t n = 5000;
    std::vector<Row> rows(n);
    for (std::size_t i = 0; i < n; ++i) {
        rows[i] = Row{static_cast<std::int64_t>(i) * 3 - 7000, static_cast<double>(i) * 0.5};
    }
    std::shuffle(rows.begin(), rows.end(), std::mt19937(17));
    std::vector<Row> expected = rows;
    std::sort(expected.begin(), expected.end(), ByKey{});
    // 1: 5000 runs of one record (79 merge passes of 64 first); 7: 715 runs; 100: 50 runs, one
    // merge; n and above: in memory.
    for (const std::size_t capacity : {std::size_t{1}, std::size_t{7}, std::size_t{100}, n, 2 * n}) {
        test::ScratchDir dir;
        const std::filesystem::path runs = dir.path() / "runs";
        {
            ExternalSorter<Row, ByKey> sorter(runs, "t", capacity, ByKey{}, fail);
            for (const Row& r : rows) {
                sorter.add(r);
            }
            EXPECT_EQ(sorter.size(), n);
            EXPECT_EQ(sorter.spilled(), capacity < n) << capacity;
            EXPECT_EQ(files_in(runs) > 0, capacity < n) << capacity;
            sorter.finish();
            if (capacity < n) {
                EXPECT_LE(files_in(runs), (ExternalSorter<Row, ByKey>::k_fan_in)) << "merged to at most one pass's runs";
            }
            Row r;
            std::size_t i = 0;
            while (sorter.next(r)) {
                ASSERT_LT(i, n);
                ASSERT_EQ(r.key, expected[i].key) << "capacity " << capacity << ", record " << i;
                ASSERT_EQ(r.payload, expected[i].payload);
                ++i;
            }
            EXPECT_EQ(i, n) << capacity;
            EXPECT_FALSE(sorter.next(r)) << "stays at its end";
        }
        EXPECT_EQ(files_in(runs), 0u) << "runs removed, capacity " << capacity;
    }
}

TEST(ExternalSorter, NoRecordsReadsNothing)
{
    test::ScratchDir dir;
    ExternalSorter<Row, ByKey> sorter(dir.path() / "runs", "t", 4, ByKey{}, fail);
    sorter.finish();
    Row r;
    EXPECT_FALSE(sorter.next(r));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "runs"));
}

TEST(ExternalSorter, ADirectoryThatCannotBeMadeIsNamed)
{
    test::ScratchDir dir;
    const std::filesystem::path file = dir.path() / "a-file";
    std::ofstream(file) << "x";
    ExternalSorter<Row, ByKey> sorter(file / "runs", "t", 2, ByKey{}, fail);
    sorter.add(Row{1, 0});
    sorter.add(Row{2, 0});
    try {
        sorter.add(Row{3, 0}); // the first run goes to disk
        FAIL() << "no failure";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find((file / "runs").string()), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace trisnap
