#include "app/allocator.hpp"

#include "app/memory.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
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

namespace fs = std::filesystem;

std::string first_line(const char* path)
{
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    return line;
}

#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
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

/// The heap grown by `bytes` (blocks malloc'ed and freed again: the heap keeps them in its top,
/// which is never trimmed) and that range advised for huge pages.
void advise_huge_heap(std::uint64_t bytes)
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
    if (!blocks.empty() && to > from && inside_the_heap(from, to)) {
        madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE); // refused: the heap stays as it was
    }
    for (void* p : blocks) {
        std::free(p);
    }
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

bool huge_pages_wanted()
{
    const char* setting = std::getenv("TRISNAP_HUGE_PAGES");
    if (setting != nullptr && std::strcmp(setting, "0") == 0) {
        return false;
    }
    const bool forced = setting != nullptr && std::strcmp(setting, "1") == 0;
    return first_line("/sys/kernel/mm/transparent_hugepage/enabled").find("[madvise]") != std::string::npos &&
           first_line("/proc/sys/vm/overcommit_memory") != "2" && (forced || !free_pages_reported("/sys/bus/virtio/devices"));
}
#endif

} // namespace

bool free_pages_reported(const std::string& virtio_devices)
{
    constexpr std::size_t k_reporting = 5; // VIRTIO_BALLOON_F_REPORTING
    std::error_code ec;
    for (fs::directory_iterator it(virtio_devices, ec), end; !ec && it != end; it.increment(ec)) {
        const fs::path device = it->path();
        if (first_line((device / "device").c_str()) != "0x0005") { // a memory balloon
            continue;
        }
        const std::string features = first_line((device / "features").c_str());
        if (features.size() > k_reporting && features[k_reporting] == '1') {
            return true;
        }
    }
    return false;
}

void advise_thread_heap()
{
#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
    if (!huge_pages_wanted()) {
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
#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
    if (!huge_pages_wanted()) {
        return;
    }
    const std::uint64_t bytes = std::min({k_most, physical_memory() / 8, quarter_of_limit(RLIMIT_DATA), quarter_of_limit(RLIMIT_AS)});
    advise_huge_heap(bytes);
#endif
}

} // namespace trisnap
