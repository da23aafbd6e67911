#pragma once
// `trisnap assess`: measures how a snapped layer relates to its original, for any two OGR layers
// (trisnap, GEOS or CGAL output alike). Layers are read with src/io's reader (the one `snap`
// uses); every measure goes through spatial indexes (STR trees), parallel loops are oneTBB, and
// every example list is sorted, so results do not depend on the thread count. Shares no code
// with src/core: it judges the engine independently.
//
// Definitions (distances in layer units):
//  - features are matched by FID, or by the value of `key_field` (k-th occurrence to k-th); an
//    `orig_fid` field of the snapped layer (trisnap's for formats that renumber) stands for its FID;
//  - missing: non-empty input features without a non-empty output; extra: output features whose
//    key is not in the input; empty: output features with no geometry or an empty one;
//  - unmeasurable: a feature with a coordinate that is not finite or beyond ±1e150; kept out of
//    every measure (an unmeasurable output polygon or line also counts as invalid);
//  - attribute mismatch: matched features whose values differ in a field both layers have;
//  - invalid / overlaps / gaps / area: polygon features only (validity by GDAL's IsValid);
//  - overlap: a pair of output polygons whose interiors meet (intersection area > 0); "new" when
//    their input features did not overlap;
//  - new gap: an input pair sharing boundary longer than 2T whose outputs share none;
//  - crossing: two distinct output segments meeting other than at a common endpoint (proper
//    crossings, an endpoint on the other's interior, collinear overlaps), within one feature too;
//    "new" unless the input features of the two segments (or the one feature) crossed already;
//  - separations: over distinct coordinates (exact equality decides "same vertex"); a breach is
//    a vertex whose nearest other vertex is closer than T, or nearest non-incident edge closer
//    than T/2;
//  - Hausdorff: per matched feature, between input and output boundaries/lines, both directions,
//    exact up to T/1000 (branch and bound along edges, see hausdorff.cpp); drift is > 2T.
// The contract holds when no defect is left that is new and not explained by the snap report
// (`report`, see excuses.hpp for which code explains what).
#include "assess/sites.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

class GDALDataset;
class OGRLayer;

namespace trisnap {

namespace assess {
struct LayerData;
struct SnapReport;
} // namespace assess

struct AssessOptions {
    double tolerance = 0;   // T, > 0
    std::string key_field;  // empty: match by FID
    std::size_t max_examples = 20;
    std::size_t worst = 5;                       // sites in AssessReport::worst
    const assess::SnapReport* report = nullptr; // explains defects; null: none
};

/// One example of a defect or an extreme; which fields mean what depends on the list.
struct AssessExample {
    std::int64_t fid_a = -1;   // input FID, or the first output feature of a pair
    std::int64_t fid_b = -1;   // output FID, or the second output feature of a pair
    double x = 0, y = 0;       // where
    double x2 = 0, y2 = 0;     // second point (the other vertex; closest point on the edge)
    double value = 0;          // area, distance or length, by list
    std::string text;          // reason, or field name and values
    std::array<double, 4> edge{}; // the edge of a vertex-edge pair (x1, y1, x2, y2); a lost feature's box
    bool is_new = true;        // overlaps, crossings: not in the input already
    std::string excused_by;    // the snap report's codes that explain it
};

/// How many defects of one kind the snap report explains.
struct ExcusedCounts {
    std::int64_t missing = 0, drift = 0, gaps = 0, separations = 0;
    std::int64_t total() const { return missing + drift + gaps + separations; }
};

struct AssessReport {
    std::string layer_a, layer_b;
    std::string matched_by; // "fid", "orig_fid" or "key FIELD"
    std::string snap_report; // the --report file, empty without
    double tolerance = 0;
    std::int64_t n_in = 0, n_out = 0, n_matched = 0, n_missing = 0, n_extra = 0, n_attr_mismatch = 0;
    std::int64_t n_invalid = 0, n_empty = 0, n_overlaps = 0, gaps_new = 0, n_crossings = 0;
    std::int64_t n_unmeasurable = 0;        // features of either layer kept out of the measures
    std::int64_t n_shared_in = 0;           // input pairs sharing > 2T of boundary
    std::int64_t n_overlaps_new = 0;        // overlapping output pairs whose inputs did not overlap
    std::int64_t n_crossings_new = 0;       // crossings whose input features did not cross
    std::int64_t n_vv_breaches = 0;         // vertices with another vertex closer than T
    std::int64_t n_ve_breaches = 0;         // vertices with a non-incident edge closer than T/2
    std::int64_t n_drift = 0;               // matched features with Hausdorff > 2T
    ExcusedCounts excused_counts;
    double overlap_area = 0;
    std::optional<double> min_vertex_vertex; // none when fewer than two distinct vertices
    std::optional<double> min_vertex_edge;   // none when no vertex has a non-incident edge
    double max_hausdorff = 0, p99_hausdorff = 0;
    double area_in = 0, area_out = 0, area_change = 0;
    double seconds = 0;
    std::vector<std::pair<std::string, double>> timings; // seconds per phase, in run order

    std::vector<AssessExample> invalid, empty, overlaps, gaps_new_examples, crossings, closest_vertex_edge,
        closest_vertex_vertex, largest_hausdorff, missing, extra, attr_mismatch, unmeasurable, excused;
    std::vector<AssessExample> problems; // located problems of the snap report (value: code, text: name)
    std::vector<assess::Site> worst;     // the worst sites, in the order shared with render

    /// No defect left that is new and unexplained: 0 invalid, new crossings, new overlaps;
    /// every missing feature, new gap, drift > 2T and separation breach explained by the report.
    bool contract_holds() const;
    /// Which parts of the contract fail, e.g. "3 new crossings; 2 vertex-edge < T/2 (min 0.2 T)".
    std::vector<std::string> contract_failures() const;
};

/// A layer to read: the dataset as well, since OSM layers are read through it (interleaved).
struct LayerSource {
    GDALDataset& dataset;
    OGRLayer& layer;
};

/// Measures `snapped` against `original`. Throws io_error naming the file when a feature cannot
/// be read or a layer yields no feature, std::invalid_argument for an unknown key field.
AssessReport assess_layers(LayerSource original, LayerSource snapped, const AssessOptions& options);

/// The same on layers already read (assess::read_pair), for callers that also draw them.
AssessReport assess_data(const assess::LayerData& a, const assess::LayerData& b, const std::string& matched_by,
                         const AssessOptions& options);

/// The report as JSON text (the keys documented in README.md, "trisnap assess").
std::string assess_report_json(const AssessReport& report);

/// A readable table for stdout.
std::string assess_report_table(const AssessReport& report);

/// Every example of the report, and the snap report's located problems, as sites: grouped by
/// kind, worst first within a kind (render marks them; AssessReport::worst picks from them).
std::vector<assess::Site> report_sites(const AssessReport& report);

/// One line per site: "#1 drift 30.7 T (> 2T), fid 170 at 84924.2, 447578.9; excused by 209 ...".
std::vector<std::string> worst_site_lines(const std::vector<assess::Site>& sites, double tolerance);

/// "holds" or "does NOT hold: 3 new crossings; ...;".
std::string contract_verdict(const AssessReport& report);

} // namespace trisnap
