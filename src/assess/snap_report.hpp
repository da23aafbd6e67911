#pragma once
// The problems of a `trisnap snap --report` file, read for `assess --report` (which defects the
// report explains) and `render --report` (problems marked on the map). One reader for both.
#include "assess/geometry.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace trisnap::assess {

struct ReportedProblem {
    std::int64_t fid = -1;
    int code = 0;
    std::string name;     ///< "thin_part_collapsed"
    std::optional<Pt> at; ///< none when the report gives no place
};

struct SnapReport {
    std::string path;
    std::vector<ReportedProblem> problems;      ///< in file order
    std::optional<double> tolerance;            ///< config.tolerance_layer_units
    std::optional<std::int64_t> input_features; ///< counts.input
};

/// Reads the report. Throws io_error naming the file when it cannot be read, is not JSON, or has
/// no `problems` list (not a `trisnap snap --report` file).
SnapReport read_snap_report(const std::string& path);

} // namespace trisnap::assess
