#pragma once
// The run manifest (--report FILE.json) and the terminal summary.
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "io/commit_group.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>

namespace trisnap {

/// Peak resident memory of this process so far, in MB (getrusage).
double peak_memory_mb();

/// Writes `document` as document.dump(2) would (strings that are not valid UTF-8 get U+FFFD
/// for each bad byte), with its last member `key`, an empty array there, holding the items
/// `items` gives one at a time: the text is the same, byte for byte, and the array is never held
/// whole. Throws std::logic_error when `key` is not the last member or not an empty array.
void write_json_streaming_last_array(
    const nlohmann::ordered_json& document, const std::string& key,
    const std::function<void(const std::function<void(const nlohmann::ordered_json&)>&)>& items,
    const std::function<void(std::string_view)>& put);

/// The manifest as JSON text: version, resolved config, counts, timings, peak memory, problems
/// (read back from the run's problem log one at a time, while its work files are there).
void write_report(const Plan& plan, const RunResult& result, double total_seconds,
                  const std::function<void(std::string_view)>& put);
std::string report_text(const Plan& plan, const RunResult& result, double total_seconds);

/// Writes the manifest to its temporary file and stages it in `group`, to be renamed with OUT.
void stage_report(CommitGroup& group, const std::string& path, const Plan& plan, const RunResult& result,
                  double total_seconds);

/// A few lines for people: counts, problems by code, time, memory.
void print_summary(std::ostream& out, const Plan& plan, const RunResult& result, double total_seconds);

} // namespace trisnap
