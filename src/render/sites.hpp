#pragma once
// What snapping did, as places to look at: collapses (input features with no output), drift
// (how far a feature moved), the closest vertex–vertex and vertex–edge pairs of the result, and
// problems from a `trisnap snap --report` file. Measured here with grid indexes, independently
// of src/core, in O(n log n) for n vertices.
#include "render/types.hpp"

#include <optional>
#include <string>
#include <vector>

namespace trisnap::render {

enum class SiteKind { collapse, drift, vertex_edge, vertex_vertex, problem };
inline constexpr int k_site_kinds = 5;

/// "collapse", "drift", "vertex-edge", "vertex-vertex", "problem" (also the SVG class suffix).
const char* kind_name(SiteKind kind);

struct Site {
    SiteKind kind = SiteKind::problem;
    XY at;                 ///< the vertex (pairs, drift), the feature's centre (collapse), the report's x/y
    XY other;              ///< the other vertex or the nearest point on the edge / other layer
    double value = 0;      ///< distance in layer units; collapse: mean width 2A/P (polygons) or length
    std::int64_t fid = -1; ///< feature of `at`
    std::int64_t fid2 = -1;///< feature of `other` (pairs)
    int code = 0;          ///< problem code
    std::string name;      ///< problem name; collapse: "width" or "length" (what `value` is)
    Box extent;            ///< collapse: the lost feature's box
    bool defect = false;   ///< breaks the contract at T: v-v < T, v-e < T/2, drift > 2T, any collapse
};

/// All sites, grouped by kind in enum order, worst first within a kind. Without `out` only the
/// pairs of `in` are measured; without a tolerance no pairs are measured (they are defined
/// relative to T) but collapses and drift are.
/// `problems` (from read_problem_sites) are merged in.
std::vector<Site> find_sites(const Layer& in, const Layer* out, std::optional<double> tolerance,
                             std::vector<Site> problems = {});

/// The problems of a `trisnap snap --report` JSON file that have a location, and its tolerance
/// in layer units (config.tolerance_layer_units) when present. Throws io_error.
std::vector<Site> read_problem_sites(const std::string& path, std::optional<double>& tolerance);

/// Up to n sites: contract breaches first, then the worst of the rest, taking kinds in turn so
/// every kind present is shown; a site closer than `spacing` to one already taken is skipped.
std::vector<Site> pick_worst(const std::vector<Site>& sites, std::size_t n, double spacing);

/// Half the side of the square a panel shows around `site`.
double panel_half_size(const Site& site, double tolerance);

} // namespace trisnap::render
