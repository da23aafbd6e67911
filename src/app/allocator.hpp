#pragma once
// The process's malloc: glibc's, told to keep what the process frees for its next allocations
// instead of handing it back to the kernel and faulting it in again. Measured (2026-11-27, one
// and two threads, medians of 3, load 1.4 on 2 cores; REPORT.md "Lean engine"): against oneTBB's
// tbbmalloc_proxy, which this replaced, CPU -18 to -23 % on every shared layer, 2-thread wall
// -15 to -25 %, peak memory equal or lower. A page fault costs ~7 us on this VM, and tbbmalloc
// unmapped and re-mapped 330 of its 480 MB on Natural Earth's land (97 k faults; 45 k now).
#include <climits> // first: it brings glibc's <features.h>, which defines __GLIBC__
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace trisnap {

/// Call first thing in main(). Blocks up to 32 MiB (the most glibc takes) come from the heap,
/// not from a mapping of their own, and the heap's free top is never trimmed: freed memory is
/// reused, peak memory is unchanged (it is what was live at the worst moment).
inline void keep_freed_memory()
{
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

} // namespace trisnap
