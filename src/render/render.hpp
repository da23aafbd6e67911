#pragma once
// `trisnap render`: a picture of what snapping did. Input thin, output bold, collapses, drift,
// the closest vertex–vertex and vertex–edge pairs and reported problems circled, a scale bar
// and a legend; with `worst` > 0 one zoomed panel per worst site instead of the overview.
// Same inputs, same bytes (SVG or PNG).
#include "render/sites.hpp"

#include <optional>
#include <string>

namespace trisnap::render {

struct RenderOptions {
    std::string input;
    std::string snapped;         ///< empty: draw the input alone (its own closest pairs)
    std::string output;          ///< .svg or .png (case-insensitive)
    std::string layer_a;         ///< layer of `input` (empty: the only polygon/line layer)
    std::string layer_b;         ///< layer of `snapped`
    std::string problems_report; ///< a `trisnap snap --report` JSON file
    std::string key;             ///< integer field matching features (default: orig_fid, else FID)
    std::optional<Box> bbox;     ///< read and show only this part (layer units)
    std::optional<double> tolerance; ///< T; else the report's tolerance_layer_units
    int worst = 0;               ///< > 0: panels of the N worst sites
    int width = 1200;            ///< picture width in pixels
};

struct RenderResult {
    int width = 0;
    int height = 0;
    std::size_t panels = 0;          ///< 0 for the overview
    std::size_t features_in = 0;
    std::size_t features_out = 0;
    std::vector<Site> sites;         ///< everything found, grouped by kind, worst first
    std::vector<Site> shown;         ///< the sites marked or given a panel
    std::optional<double> tolerance; ///< the T used
};

/// True for names ending in .svg or .png (any case); `png` tells which.
bool picture_format(const std::string& path, bool& png);

/// Checks options that need no I/O; throws argument_error.
void check_options(const RenderOptions& options);

/// Reads, measures, draws and writes. Throws argument_error (e.g. --worst without a
/// tolerance), io_error (unreadable input, nothing to draw, unwritable output).
RenderResult render(const RenderOptions& options);

/// One line per kind: count, breaches of the contract, worst value (as a multiple of T).
std::string summarise(const RenderResult& result);

} // namespace trisnap::render
