#include "app/allocator.hpp"

#include "app/memory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
#include <malloc.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace trisnap {
namespace {

HugePageChoice g_choice; // written once, by keep_freed_memory() before any other thread runs

#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
std::string first_line(const char* path)
{
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    return line;
}

constexpr std::size_t k_block = std::size_t{16} << 20;  // below the mmap threshold: taken from the heap
constexpr std::uint64_t k_most = std::uint64_t{1} << 30; // and below the trim threshold (INT_MAX) once freed

std::uint64_t quarter_of_limit(int resource)
{
    rlimit r{};
    if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) {
        return UINT64_MAX;
    }
    return static_cast<std::uint64_t>(r.rlim_cur) / 4;
}

/// Whether [from, to) lies inside one mapping of the heap ("[heap]" in /proc/self/maps): the
/// blocks came from growing it, none from a mapping of their own somewhere else (glibc falls back
/// to mmap when the heap cannot grow in place), so advising the range touches nothing else.
bool inside_the_heap(std::uintptr_t from, std::uintptr_t to)
{
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line)) {
        if (line.size() < 6 || line.compare(line.size() - 6, 6, "[heap]") != 0) {
            continue;
        }
        const std::size_t dash = line.find('-');
        const std::size_t space = line.find(' ', dash);
        if (dash == std::string::npos || space == std::string::npos) {
            continue;
        }
        const auto lo = static_cast<std::uintptr_t>(std::stoull(line.substr(0, dash), nullptr, 16));
        const auto hi = static_cast<std::uintptr_t>(std::stoull(line.substr(dash + 1, space - dash - 1), nullptr, 16));
        if (lo <= from && to <= hi) {
            return true;
        }
    }
    return false;
}

/// Seconds to touch [at, at + bytes) once per 4 KiB, by writing: as fresh memory is first
/// touched (a read first would map the zero page and fault again on the write).
double touch(char* at, std::size_t bytes)
{
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < bytes; i += 4096) {
        *static_cast<volatile char*>(at + i) = 0;
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The probe: in `block` (ours, at least 6 MiB), 512 KiB at a 2 MiB boundary touched in 4 KiB
/// pages (the time scaled to 2 MiB: a quarter of the cost, ~1.3 ms on the team's VM), then the
/// next 2 MiB advised for a huge page and touched. False where the kernel refused the advice.
bool probe_huge_pages(char* block, std::size_t bytes, double& small, double& huge)
{
    constexpr std::uintptr_t k_huge = std::uintptr_t{2} << 20;
    const auto start = (reinterpret_cast<std::uintptr_t>(block) + k_huge - 1) & ~(k_huge - 1);
    if (start + 2 * k_huge > reinterpret_cast<std::uintptr_t>(block) + bytes) {
        return false;
    }
    char* const small_pages = reinterpret_cast<char*>(start);
    char* const huge_page = small_pages + k_huge;
    if (madvise(huge_page, k_huge, MADV_HUGEPAGE) != 0) {
        return false;
    }
    small = 4 * touch(small_pages, k_huge / 4);
    huge = touch(huge_page, k_huge);
    return true;
}

/// The heap grown by `bytes` (blocks malloc'ed and freed again: the heap keeps them in its top,
/// which is never trimmed) and that range advised for huge pages where `probe` is false or the
/// probe in its first block (ours until freed) finds them faster. False where the heap did not
/// grow in place (nothing probed or advised).
bool advise_huge_heap(std::uint64_t bytes, bool probe)
{
    std::vector<void*> blocks;
    blocks.reserve(static_cast<std::size_t>(bytes / k_block) + 1);
    std::uintptr_t lo = UINTPTR_MAX;
    std::uintptr_t hi = 0;
    for (std::uint64_t got = 0; got + k_block <= bytes; got += k_block) {
        void* p = std::malloc(k_block);
        if (p == nullptr) {
            break; // as far as the heap would grow
        }
        blocks.push_back(p);
        lo = std::min(lo, reinterpret_cast<std::uintptr_t>(p));
        hi = std::max(hi, reinterpret_cast<std::uintptr_t>(p) + k_block);
    }
    const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGE_SIZE));
    const std::uintptr_t from = lo & ~(page - 1); // the page of the first block's header too
    const std::uintptr_t to = hi & ~(page - 1);
    const bool grown = !blocks.empty() && to > from && inside_the_heap(from, to);
    bool advise = grown;
    if (advise && probe) {
        // A refused probe leaves the reason as it was (unavailable): the range would be refused too.
        advise = probe_huge_pages(static_cast<char*>(blocks.front()), k_block, g_choice.small_seconds, g_choice.huge_seconds);
        if (advise) {
            g_choice.why = HugePageChoice::Why::probed;
            advise = g_choice.huge_seconds < g_choice.small_seconds;
        }
    }
    if (advise) {
        g_choice.advised = madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE) == 0; // refused: the heap stays as it was
    }
    for (void* p : blocks) {
        std::free(p);
    }
    return grown;
}

/// Whether some mapping of /proc/self/maps starts at `at` and is not the main heap.
bool a_mapping_starts_at(std::uintptr_t at)
{
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line)) {
        const std::size_t dash = line.find('-');
        if (dash == std::string::npos) {
            continue;
        }
        if (static_cast<std::uintptr_t>(std::stoull(line.substr(0, dash), nullptr, 16)) == at) {
            return line.find("[heap]") == std::string::npos;
        }
    }
    return false;
}

bool huge_pages_on_request()
{
    return first_line("/sys/kernel/mm/transparent_hugepage/enabled").find("[madvise]") != std::string::npos &&
           first_line("/proc/sys/vm/overcommit_memory") != "2";
}
#endif

} // namespace

void advise_thread_heap()
{
#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
    if (!g_choice.advised) {
        return;
    }
    // glibc's heaps for threads other than the first are mappings of 64 MiB (twice the largest
    // mmap threshold), aligned to their size, reserved at once and made writable as they grow.
    constexpr std::uintptr_t k_thread_heap = std::uintptr_t{64} << 20;
    void* probe = std::malloc(64);
    if (probe == nullptr) {
        return;
    }
    const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(probe) & ~(k_thread_heap - 1);
    std::free(probe);
    if (!a_mapping_starts_at(base)) {
        return;
    }
    madvise(reinterpret_cast<void*>(base), k_thread_heap, MADV_HUGEPAGE); // refused: it stays as it was
    // The heap made writable up to ~30 MiB at once (a block below the mmap threshold, freed into
    // the heap's top, which is not trimmed): glibc otherwise widens it by mprotect() as it grows,
    // each call holding the process's memory map lock against the other thread's page faults.
    std::free(std::malloc(std::size_t{30} << 20));
#endif
}

void keep_freed_memory()
{
    const char* setting = std::getenv("TRISNAP_HUGE_PAGES");
    const bool off = setting != nullptr && std::strcmp(setting, "0") == 0;
    const bool forced = setting != nullptr && std::strcmp(setting, "1") == 0;
    if (setting != nullptr && !off && !forced) {
        g_choice.ignored_setting = setting;
    }
#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
    if (off) {
        g_choice.why = HugePageChoice::Why::off_by_env;
        return;
    }
    g_choice.why = forced ? HugePageChoice::Why::forced_by_env : HugePageChoice::Why::unavailable;
    const std::uint64_t bytes = std::min({k_most, physical_memory() / 8, quarter_of_limit(RLIMIT_DATA), quarter_of_limit(RLIMIT_AS)});
    if (!huge_pages_on_request() || !advise_huge_heap(bytes, !forced)) {
        g_choice.why = HugePageChoice::Why::unavailable;
    }
#else
    g_choice.why = off ? HugePageChoice::Why::off_by_env : HugePageChoice::Why::not_glibc;
#endif
}

const HugePageChoice& huge_page_choice() { return g_choice; }

std::string describe(const HugePageChoice& c)
{
    std::string text;
    switch (c.why) {
    case HugePageChoice::Why::not_called: text = "not set up"; break;
    case HugePageChoice::Why::not_glibc: text = "4 KiB pages (not glibc's malloc)"; break;
    case HugePageChoice::Why::unavailable:
        text = "4 KiB pages (no huge pages on request here, or no room for the heap to grow under the limits)";
        break;
    case HugePageChoice::Why::off_by_env: text = "4 KiB pages (TRISNAP_HUGE_PAGES=0)"; break;
    case HugePageChoice::Why::forced_by_env:
        text = c.advised ? "huge pages (TRISNAP_HUGE_PAGES=1)" : "4 KiB pages (TRISNAP_HUGE_PAGES=1, but the kernel refused)";
        break;
    case HugePageChoice::Why::probed:
        text = fmt::format("{} (probe: a 2 MiB huge page touched in {:.1f} ms, 4 KiB pages at {:.1f} ms per 2 MiB)",
                           c.advised ? "huge pages" : "4 KiB pages", c.huge_seconds * 1e3, c.small_seconds * 1e3);
        break;
    }
    if (!c.ignored_setting.empty()) {
        text += fmt::format("; TRISNAP_HUGE_PAGES={} ignored (0 or 1)", c.ignored_setting);
    }
    return text;
}

} // namespace trisnap
