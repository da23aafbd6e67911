#include "core/snap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace trisnap {

SnapStats& SnapStats::operator+=(const SnapStats& o)
{
    input_features += o.input_features;
    input_vertices += o.input_vertices;
    triangulation_vertices += o.triangulation_vertices;
    output_vertices += o.output_vertices;
    intersections += o.intersections;
    merges += o.merges;
    splits += o.splits;
    rounds = std::max(rounds, o.rounds);
    faces_visited += o.faces_visited;
    fixpoint_misses += o.fixpoint_misses;
    collapsed_features += o.collapsed_features;
    max_displacement = std::max(max_displacement, o.max_displacement);
    seconds_triangulate += o.seconds_triangulate;
    seconds_snap += o.seconds_snap;
    seconds_label += o.seconds_label;
    seconds_extract += o.seconds_extract;
    return *this;
}

std::string validate(const SnapOptions& o)
{
    auto fmt = [](const char* what, double v) { return std::string(what) + ", got " + std::to_string(v); };
    if (!std::isfinite(o.tolerance) || o.tolerance <= 0) return fmt("tolerance must be finite and > 0", o.tolerance);
    if (const std::string range = tolerance_range_error(o.tolerance); !range.empty()) {
        return range;
    }
    if (!(o.edge_separation > 0 && o.edge_separation <= 1)) return fmt("edge_separation must be in (0, 1]", o.edge_separation);
    if (!(o.sliver_factor >= 0 && o.sliver_factor <= 1)) return fmt("sliver_factor must be in [0, 1]", o.sliver_factor);
    if (!(o.grid >= 0 && o.grid <= o.tolerance / 4)) return fmt("grid must be >= 0 and <= tolerance/4", o.grid);
    if (!(o.max_drift_factor > 0) || !std::isfinite(o.max_drift_factor)) return fmt("max_drift_factor must be finite and > 0", o.max_drift_factor);
    const Region& r = o.report_region;
    if (!(r.xmin < r.xmax && r.ymin < r.ymax)) return "report_region must have xmin < xmax and ymin < ymax";
    for (const Region& c : o.report_cores) {
        if (!(c.xmin < c.xmax && c.ymin < c.ymax)) return "report_cores must have xmin < xmax and ymin < ymax";
    }
    const Region& d = o.data_extent;
    if (!(d.xmin <= d.xmax && d.ymin <= d.ymax)) return "data_extent must have xmin <= xmax and ymin <= ymax";
    return {};
}

} // namespace trisnap
