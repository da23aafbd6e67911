#pragma once
// `trisnap assess`: measures how a snapped layer relates to its original, for any two OGR layers
// (trisnap, GEOS or CGAL output alike). Every measure goes through spatial indexes (STR trees),
// parallel loops are oneTBB, and every example list is sorted, so results do not depend on the
// thread count. Shares no code with src/core: it judges the engine independently.
//
// Definitions (distances in layer units):
//  - features are matched by FID, or by the value of `key_field` (k-th occurrence to k-th); an
//    `orig_fid` field of the snapped layer (trisnap's for formats that renumber) stands for its FID;
//  - missing: non-empty input features without a non-empty output; extra: output features whose
//    key is not in the input; empty: output features with no geometry or an empty one;
//  - attribute mismatch: matched features whose values differ in a field both layers have;
//  - invalid / overlaps / gaps / area: polygon features only (validity by GDAL's IsValid);
//  - overlap: a pair of output polygons whose interiors meet (intersection area > 0); "new" when
//    their input features did not overlap;
//  - new gap: an input pair sharing boundary longer than 2T whose outputs share none;
//  - crossing: two distinct output segments meeting other than at a common endpoint (proper
//    crossings, an endpoint on the other's interior, collinear overlaps), within one feature too;
//  - separations: over distinct coordinates (exact equality decides "same vertex");
//  - Hausdorff: per matched feature, between input and output boundaries/lines, both directions,
//    exact up to T/1000 (branch and bound along edges, see hausdorff.cpp).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

class OGRLayer;

namespace trisnap {

struct AssessOptions {
    double tolerance = 0;   // T, > 0
    std::string key_field;  // empty: match by FID
    std::size_t max_examples = 20;
};

/// One example of a defect or an extreme; which fields mean what depends on the list.
struct AssessExample {
    std::int64_t fid_a = -1;   // input FID, or the first output feature of a pair
    std::int64_t fid_b = -1;   // output FID, or the second output feature of a pair
    double x = 0, y = 0;       // where
    double x2 = 0, y2 = 0;     // second point (the other vertex; closest point on the edge)
    double value = 0;          // area, distance or length, by list
    std::string text;          // reason, or field name and values
    std::array<double, 4> edge{}; // the edge of a vertex-edge pair: x1, y1, x2, y2
};

struct AssessReport {
    std::string layer_a, layer_b;
    std::string matched_by; // "fid", "orig_fid" or "key FIELD"
    double tolerance = 0;
    std::int64_t n_in = 0, n_out = 0, n_matched = 0, n_missing = 0, n_extra = 0, n_attr_mismatch = 0;
    std::int64_t n_invalid = 0, n_empty = 0, n_overlaps = 0, gaps_new = 0, n_crossings = 0;
    std::int64_t n_shared_in = 0;           // input pairs sharing > 2T of boundary
    std::int64_t n_overlaps_new = 0;        // overlapping output pairs whose inputs did not overlap
    double overlap_area = 0;
    std::optional<double> min_vertex_vertex; // none when fewer than two distinct vertices
    std::optional<double> min_vertex_edge;   // none when no vertex has a non-incident edge
    double max_hausdorff = 0, p99_hausdorff = 0;
    double area_in = 0, area_out = 0, area_change = 0;
    double seconds = 0;
    std::vector<std::pair<std::string, double>> timings; // seconds per phase, in run order

    std::vector<AssessExample> invalid, empty, overlaps, gaps_new_examples, crossings, closest_vertex_edge,
        closest_vertex_vertex, largest_hausdorff, missing, extra, attr_mismatch;

    /// 0 invalid, crossings, overlaps, new gaps and missing; min_vv >= T, min_ve >= T/2,
    /// max Hausdorff <= 2T.
    bool contract_holds() const;
    /// Which parts of the contract fail, e.g. "3 crossings; min_vertex_edge 0.2 T < T/2".
    std::vector<std::string> contract_failures() const;
};

/// Measures `snapped` against `original`. Throws std::runtime_error naming the layer when a
/// feature cannot be read, argument_error-like std::invalid_argument for an unknown key field.
AssessReport assess_layers(OGRLayer& original, OGRLayer& snapped, const AssessOptions& options);

/// The report as JSON text (the keys documented in README.md, "trisnap assess").
std::string assess_report_json(const AssessReport& report);

/// A readable table for stdout.
std::string assess_report_table(const AssessReport& report);

} // namespace trisnap
