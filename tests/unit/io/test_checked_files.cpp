// The checking file system (io/checked_files.hpp): bytes written through it arrive whole, a
// failed write is remembered, and the descriptor each written file keeps for its writeback hints
// is closed with it.
#include "io/checked_files.hpp"
#include "scratch_dir.hpp"

#include <cpl_vsi.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace trisnap {
namespace {
namespace fs = std::filesystem;

std::size_t open_descriptors()
{
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator("/proc/self/fd")) {
        ++n;
    }
    return n;
}

TEST(CheckedFiles, ManyMegabytesArriveWholeAndTheFileLeavesNoDescriptorOpen)
{
    test::ScratchDir scratch;
    const fs::path file = scratch.path() / "out.bin";
    std::string chunk(4096, '\0');
    for (std::size_t i = 0; i < chunk.size(); ++i) {
        chunk[i] = static_cast<char>(i * 31 + 7);
    }
    constexpr std::size_t k_chunks = 5000; // 20 MB: past the writeback hint's step more than once
    const std::size_t before = open_descriptors();
    VSILFILE* f = VSIFOpenL(checked_path(file).c_str(), "wb");
    ASSERT_NE(f, nullptr);
    for (std::size_t k = 0; k < k_chunks; ++k) {
        ASSERT_EQ(VSIFWriteL(chunk.data(), 1, chunk.size(), f), chunk.size());
    }
    ASSERT_EQ(VSIFCloseL(f), 0);
    EXPECT_EQ(open_descriptors(), before);
    EXPECT_EQ(take_write_failure(scratch.path()), "");
    ASSERT_EQ(fs::file_size(file), k_chunks * chunk.size());
    std::ifstream in(file, std::ios::binary);
    std::string back(chunk.size(), '\0');
    for (std::size_t k = 0; k < k_chunks; ++k) {
        ASSERT_TRUE(in.read(back.data(), static_cast<std::streamsize>(back.size())));
        ASSERT_EQ(back, chunk) << "chunk " << k;
    }
}

TEST(CheckedFiles, AFullDeviceIsRememberedAndItsDescriptorClosed)
{
    if (!fs::exists("/dev/full")) {
        GTEST_SKIP() << "no /dev/full here";
    }
    const std::string chunk(1 << 20, 'x');
    const std::size_t before = open_descriptors();
    VSILFILE* f = VSIFOpenL(checked_path("/dev/full").c_str(), "wb");
    ASSERT_NE(f, nullptr);
    for (int k = 0; k < 10; ++k) {
        VSIFWriteL(chunk.data(), 1, chunk.size(), f);
    }
    VSIFCloseL(f);
    EXPECT_EQ(open_descriptors(), before);
    const std::string failure = take_write_failure("/dev");
    EXPECT_NE(failure.find("full:"), std::string::npos) << failure;
    EXPECT_NE(failure.find("No space left on device"), std::string::npos) << failure;
    EXPECT_EQ(take_write_failure("/dev"), "") << "a failure is returned once";
}

} // namespace
} // namespace trisnap
