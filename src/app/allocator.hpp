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
/// transparent huge pages (MADV_HUGEPAGE): a first touch there faults in 2 MiB, not 4 KiB (the
/// peak rounds up to them: +1 to 3 % measured). Only where the kernel's THP mode is "madvise" (with "always" every page is huge
/// already, with "never" none can be), the overcommit policy is not strict (2: the range would
/// count against it), and a quarter of RLIMIT_DATA and RLIMIT_AS allows it; at most 1/8 of the
/// memory. Nor where the hypervisor takes the guest's free memory back (free_pages_reported()):
/// there a huge page the kernel hands out is mostly one the host dropped, and its first touch
/// waits for the host to back all 2 MiB (measured 2026-12-03 on the team's VM: 5-20 ms a huge
/// page touched cold, 0.1 GB/s in a touch test, against 2 GB/s in 4 KiB pages; Andorra x43 untiled 12.8 -> 9.5 s,
/// bench/results/REPORT.md "Huge pages where the host takes free memory back").
/// TRISNAP_HUGE_PAGES=0 in the environment turns the advice off; =1 gives it even where free
/// pages are reported (the kernel's mode and the overcommit policy still decide).
void keep_freed_memory();

/// Whether a virtio memory balloon under `virtio_devices` (/sys/bus/virtio/devices: one
/// directory per device with its `device` id and `features` bit string) reports free pages to
/// the host (VIRTIO_BALLOON_F_REPORTING, bit 5): the host then drops free blocks of 2 MiB and up
/// (the kernel's page_reporting_order) ~2 s after they are freed, and backs them again on their
/// next touch. False where the directory or its files cannot be read.
bool free_pages_reported(const std::string& virtio_devices);

/// Call first thing in a thread that grows memory of its own (app/read_phase.cpp): its glibc
/// heap (a 64 MiB mapping per arena, not the first thread's) advised for transparent huge pages
/// as keep_freed_memory() advises the main heap, on the same conditions, and made writable up
/// to ~30 MiB at once. Measured 2026-11-29 on the read's second thread (124 k features of
/// Andorra x43): 0.49 s without either, 0.41 with the advice, 0.31-0.33 with both
/// (two runs of three; the third 0.46: bench/results/REPORT.md, "The read in two parts").
void advise_thread_heap();

} // namespace trisnap
