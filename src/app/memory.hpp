#pragma once
// The machine's memory, this process's resident memory and its CPU time.
#include "config/size.hpp"

#include <cstdint>

namespace trisnap {

/// Physical memory, or the cgroup's limit when that is lower (containers, Slurm jobs).
std::uint64_t physical_memory();

/// Resident memory of this process now, and its peak so far.
std::uint64_t current_rss();
std::uint64_t peak_rss();

/// CPU seconds (user + system) of all this process's threads so far.
double process_cpu_seconds();

} // namespace trisnap
