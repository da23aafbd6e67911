#pragma once
// The run manifest (--report FILE.json) and the terminal summary.
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "io/commit_group.hpp"

#include <iosfwd>
#include <map>
#include <string>

namespace trisnap {

/// Peak resident memory of this process so far, in MB (getrusage).
double peak_memory_mb();

/// Problems per code, in code order.
std::map<int, std::size_t> count_by_code(const std::vector<Problem>& problems);

/// The manifest as JSON text: version, resolved config, counts, timings, peak memory, problems.
/// Strings that are not valid UTF-8 (a file name in another encoding) get U+FFFD for each bad byte.
std::string report_text(const Plan& plan, const RunResult& result, double total_seconds);

/// Writes the manifest to its temporary file and stages it in `group`, to be renamed with OUT.
void stage_report(CommitGroup& group, const std::string& path, const Plan& plan, const RunResult& result,
                  double total_seconds);

/// A few lines for people: counts, problems by code, time, memory.
void print_summary(std::ostream& out, const Plan& plan, const RunResult& result, double total_seconds);

} // namespace trisnap
