#include "test_data.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace trisnap {
namespace {

TEST(TestData, PathsAreAbsolute) {
    EXPECT_TRUE(std::filesystem::path(TRISNAP_SHARED_DATA).is_absolute());
    EXPECT_TRUE(std::filesystem::path(TRISNAP_TEST_CASES).is_absolute());
}

TEST(TestData, SharedDataIsFoundOrReportedAbsent) {
    EXPECT_FALSE(shared_data("no/such/file.gpkg").has_value());
    const auto readme = shared_data("README.md");
    if (!readme)
        GTEST_SKIP() << "shared data not found at " << TRISNAP_SHARED_DATA;
    EXPECT_TRUE(std::filesystem::is_regular_file(*readme));
}

} // namespace
} // namespace trisnap
