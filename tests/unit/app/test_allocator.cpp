// keep_freed_memory() (app/allocator.hpp): where the kernel gives transparent huge pages on
// request, what the process allocates from its heap afterwards lies in a range advised for them
// (VmFlags "hg" in /proc/self/smaps) when TRISNAP_HUGE_PAGES=1, or without it when its probe
// found a huge page faster to touch than 4 KiB pages; TRISNAP_HUGE_PAGES=0 leaves the heap as
// it was; another value is ignored and said. Each test runs in a process of its own
// (gtest_discover_tests), so the call is that process's first.
#include "app/allocator.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace trisnap {
namespace {

std::string first_line(const char* path)
{
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    return line;
}

bool huge_pages_on_request()
{
    return first_line("/sys/kernel/mm/transparent_hugepage/enabled").find("[madvise]") != std::string::npos &&
           first_line("/proc/sys/vm/overcommit_memory") != "2";
}

/// The VmFlags of the mapping holding `p` ("" when none holds it).
std::string flags_of(const void* p)
{
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0;
        std::uintptr_t hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = lo <= at && at < hi;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) {
            return line;
        }
    }
    return "";
}

bool advised(const void* p) { return flags_of(p).find(" hg") != std::string::npos; }

TEST(Allocator, TheHeapIsAdvisedForHugePagesWhereTheKernelGivesThemOnRequest)
{
    if (!k_glibc_malloc) {
        GTEST_SKIP() << "not glibc's malloc (another C library, or AddressSanitizer's allocator)";
    }
    if (!huge_pages_on_request()) {
        GTEST_SKIP() << "this kernel does not give huge pages on request (THP mode not madvise, or strict overcommit)";
    }
    ::setenv("TRISNAP_HUGE_PAGES", "1", 1); // advised without the probe
    keep_freed_memory();
    ::unsetenv("TRISNAP_HUGE_PAGES");
    EXPECT_EQ(huge_page_choice().why, HugePageChoice::Why::forced_by_env);
    EXPECT_TRUE(huge_page_choice().advised) << describe(huge_page_choice());
    EXPECT_EQ(huge_page_choice().small_seconds, 0.0); // no probe
    // Large blocks come from the heap's top, made after the call; small ones may reuse what the
    // process freed before it (gtest's setup here; almost nothing in the trisnap binary, which
    // calls it first), but once that is used up they come from the top too.
    for (const std::size_t bytes : {std::size_t{1} << 20, std::size_t{24} << 20}) {
        const std::unique_ptr<char[]> block(new char[bytes]);
        block[0] = 1;
        EXPECT_TRUE(advised(block.get())) << bytes << " bytes at " << static_cast<const void*>(block.get()) << ": "
                                          << flags_of(block.get());
    }
    std::vector<std::unique_ptr<char[]>> small;
    for (int i = 0; i < 20000; ++i) {
        small.emplace_back(new char[1024]);
        small.back()[0] = 1;
    }
    EXPECT_TRUE(advised(small.back().get())) << flags_of(small.back().get());
}

TEST(Allocator, TheEnvironmentTurnsTheHugePagesOff)
{
    if (!k_glibc_malloc || !huge_pages_on_request()) { // nothing would be advised anyway
        GTEST_SKIP() << "no huge pages to turn off on this machine";
    }
    ::setenv("TRISNAP_HUGE_PAGES", "0", 1);
    keep_freed_memory();
    EXPECT_EQ(huge_page_choice().why, HugePageChoice::Why::off_by_env);
    EXPECT_FALSE(huge_page_choice().advised);
    const std::unique_ptr<char[]> block(new char[std::size_t{24} << 20]);
    block[0] = 1;
    EXPECT_FALSE(advised(block.get())) << flags_of(block.get());
    ::unsetenv("TRISNAP_HUGE_PAGES");
}

TEST(Allocator, WithoutTheSettingTheProbeDecides)
{
    if (!k_glibc_malloc || !huge_pages_on_request()) {
        GTEST_SKIP() << "no huge pages to give on this machine";
    }
    ::unsetenv("TRISNAP_HUGE_PAGES");
    keep_freed_memory();
    const HugePageChoice& choice = huge_page_choice();
    ASSERT_EQ(choice.why, HugePageChoice::Why::probed) << describe(choice);
    EXPECT_GT(choice.small_seconds, 0.0);
    EXPECT_GT(choice.huge_seconds, 0.0);
    EXPECT_EQ(choice.advised, choice.huge_seconds < choice.small_seconds) << describe(choice);
    const std::unique_ptr<char[]> block(new char[std::size_t{24} << 20]);
    block[0] = 1;
    EXPECT_EQ(advised(block.get()), choice.advised) << flags_of(block.get()) << "; " << describe(choice);
    EXPECT_NE(describe(choice).find(choice.advised ? "huge pages (probe: a 2 MiB huge page touched in" : "4 KiB pages (probe: a 2 MiB huge page touched in"),
              std::string::npos)
        << describe(choice);
}

TEST(Allocator, ASettingOtherThanZeroOrOneIsIgnoredAndSaid)
{
    ::setenv("TRISNAP_HUGE_PAGES", "yes", 1);
    keep_freed_memory();
    ::unsetenv("TRISNAP_HUGE_PAGES");
    const HugePageChoice& choice = huge_page_choice();
    EXPECT_EQ(choice.ignored_setting, "yes");
    EXPECT_NE(describe(choice).find("TRISNAP_HUGE_PAGES=yes ignored"), std::string::npos) << describe(choice);
    if (k_glibc_malloc && huge_pages_on_request()) {
        EXPECT_EQ(choice.why, HugePageChoice::Why::probed) << describe(choice); // as without it
    }
}

} // namespace
} // namespace trisnap
