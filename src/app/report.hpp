#pragma once
// The run manifest (--report FILE.json) and the terminal summary.
#include "app/pipeline.hpp"
#include "app/plan.hpp"

#include <iosfwd>
#include <map>
#include <string>

namespace trisnap {

/// Peak resident memory of this process so far, in MB (getrusage).
double peak_memory_mb();

/// Problems per code, in code order.
std::map<int, std::size_t> count_by_code(const std::vector<Problem>& problems);

/// Writes the manifest: version, resolved config, counts, timings, peak memory, problems.
/// Throws io_error when the file cannot be written.
void write_report(const std::string& path, const Plan& plan, const RunResult& result, double total_seconds);

/// A few lines for people: counts, problems by code, time, memory.
void print_summary(std::ostream& out, const Plan& plan, const RunResult& result, double total_seconds);

} // namespace trisnap
