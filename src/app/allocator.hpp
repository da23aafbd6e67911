#pragma once
// The process's malloc: glibc's, told to keep what the process frees for its next allocations
// instead of handing it back to the kernel and faulting it in again, and to take its heap in
// transparent huge pages where the kernel gives them on request.
//
// Measured (2026-11-27, one and two threads, medians of 3, load 1.4 on 2 cores; REPORT.md "Lean
// engine"): against oneTBB's tbbmalloc_proxy, which this replaced, CPU -18 to -23 % on every
// shared layer, 2-thread wall -15 to -25 %, peak memory equal or lower. A page fault costs ~7 us
// on this VM, and tbbmalloc unmapped and re-mapped 330 of its 480 MB on Natural Earth's land
// (97 k faults; 45 k now). The huge pages: REPORT.md "Huge pages for the heap" (2026-11-28).
#include <climits> // brings glibc's <features.h>, which defines __GLIBC__
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define TRISNAP_SANITIZED_MALLOC 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TRISNAP_SANITIZED_MALLOC 1
#endif
#endif

namespace trisnap {

/// Whether the process allocates with glibc's malloc, which keep_freed_memory() tunes (not
/// elsewhere, nor under AddressSanitizer, whose allocator replaces it).
#if defined(__GLIBC__) && !defined(TRISNAP_SANITIZED_MALLOC)
inline constexpr bool k_glibc_malloc = true;
#else
inline constexpr bool k_glibc_malloc = false;
#endif

/// Call first thing in main(). Blocks up to 32 MiB (the most glibc takes) come from the heap,
/// not from a mapping of their own, and the heap's free top is never trimmed: freed memory is
/// reused, the peak is what was live at the worst moment. Then the heap is grown at once by up
/// to 1 GiB of address space (not of memory: nothing is touched) and that range advised for
/// transparent huge pages (MADV_HUGEPAGE) where they are faster here: a first touch there
/// faults in 2 MiB, not 4 KiB (the peak rounds up to them: +1 to 3 % measured). Only where the
/// kernel's THP mode is "madvise" (with "always" every page is huge already, with "never" none
/// can be), the overcommit policy is not strict (2: the range would count against it), and a
/// quarter of RLIMIT_DATA and RLIMIT_AS allows it; at most 1/8 of the memory.
///
/// Whether they are faster is measured, not guessed (huge_page_choice()): 512 KiB of the new
/// heap touched in 4 KiB pages against the next 2 MiB as one huge page. Under a hypervisor the first
/// touch of a page costs what the host takes to back it, and that differs by machine: on the
/// team's VM of REPORT.md's twentieth session a cold huge page took 5-20 ms and 2 MiB of small
/// pages ~1 ms (Andorra x43 untiled 12.8 s advised, 9.5 s not); on the next one, with the same
/// virtio balloon reporting free pages to the host, a touch test's first pass took 2.7 ms a huge
/// page against 4.7 ms per 2 MiB of small pages, and two threads on Andorra x43 took 1.95 s
/// advised, 2.20 s not (medians of 3; bench/results/REPORT.md "Huge pages, measured at start").
/// The 2.5 MiB touched stay in the heap, for what is allocated next.
/// TRISNAP_HUGE_PAGES=0 in the environment turns the advice off, =1 gives it without the probe
/// (the kernel's mode and the overcommit policy still decide); another value is ignored, and
/// said so by huge_page_choice().ignored_setting (a warning from every command: setup_logging()).
void keep_freed_memory();

/// What keep_freed_memory() decided about huge pages, and why.
struct HugePageChoice {
    enum class Why {
        not_called,    ///< keep_freed_memory() has not run
        not_glibc,     ///< another malloc (another C library, AddressSanitizer)
        unavailable,   ///< THP mode not madvise, strict overcommit, no room for the heap under the limits, or the advice refused
        off_by_env,    ///< TRISNAP_HUGE_PAGES=0
        forced_by_env, ///< TRISNAP_HUGE_PAGES=1
        probed,        ///< the probe's times decided (advised: huge_seconds < small_seconds)
    };
    Why why = Why::not_called;
    bool advised = false;         ///< the heap's top range advised for huge pages
    double small_seconds = 0;     ///< probed: 2 MiB's worth of 4 KiB pages touched (512 KiB timed, x 4)
    double huge_seconds = 0;      ///< probed: 2 MiB touched as one huge page
    std::string ignored_setting;  ///< a TRISNAP_HUGE_PAGES that is neither 0 nor 1 ("" if none)
};
const HugePageChoice& huge_page_choice();
/// One line for the log: "huge pages (probe: a 2 MiB huge page touched in 0.1 ms, 4 KiB pages
/// at 5.0 ms per 2 MiB)" and the like.
std::string describe(const HugePageChoice& choice);

/// Call first thing in a thread that grows memory of its own (app/read_phase.cpp): its glibc
/// heap (a 64 MiB mapping per arena, not the first thread's) advised for transparent huge pages
/// as keep_freed_memory() advises the main heap, on the same conditions, and made writable up
/// to ~30 MiB at once; only where keep_freed_memory() advised the main heap. Measured
/// 2026-11-29 on the read's second thread (124 k features of Andorra x43): 0.49 s without either, 0.41 with the advice, 0.31-0.33 with both
/// (two runs of three; the third 0.46: bench/results/REPORT.md, "The read in two parts").
void advise_thread_heap();

} // namespace trisnap
