#pragma once
// `trisnap render`: a picture of what snapping did. The sites are measured and ranked by
// `assess` (src/assess) on the same layers, so the picture and `trisnap assess` agree on every
// value and on which site is worst. The overview draws the output under a thin input, every
// contract breach circled and the worst sites labelled with their rank and code; with `worst`
// > 0, one zoomed panel per worst site instead, features filled by identity (a feature and its
// snapped self share a colour). Same inputs, same bytes (SVG or PNG).
#include "assess/assess.hpp"
#include "render/sites.hpp"

#include <optional>
#include <string>

namespace trisnap::render {

struct RenderOptions {
    std::string input;
    std::string snapped;         ///< empty: draw the input alone (its own defects)
    std::string output;          ///< .svg or .png (case-insensitive)
    std::string layer_a;         ///< layer of `input` (empty: the only polygon/line layer)
    std::string layer_b;         ///< layer of `snapped`
    std::string report;          ///< a `trisnap snap --report` JSON file
    std::string key;             ///< field matching features (default: orig_fid of SNAPPED, else FID)
    std::optional<Box> bbox;     ///< read and show only this part (layer units)
    std::optional<double> tolerance;   ///< T in layer units
    std::optional<double> tolerance_m; ///< T in metres (converted on IN as snap converts it)
    int worst = 0;               ///< > 0: panels of the N worst sites
    int width = 1200;            ///< picture width in pixels
};

struct RenderResult {
    int width = 0;
    int height = 0;
    std::size_t panels = 0;          ///< 0 for the overview
    std::size_t features_in = 0;
    std::size_t features_out = 0;
    std::vector<Site> shown;         ///< the sites marked or given a panel
    std::vector<Site> ranked;        ///< the worst sites, numbered as `assess` numbers them
    std::optional<AssessReport> assessment; ///< none without a tolerance
    std::optional<double> tolerance; ///< the T used
};

/// True for names ending in .svg or .png (any case); `png` tells which.
bool picture_format(const std::string& path, bool& png);

/// Checks options that need no I/O; throws argument_error.
void check_options(const RenderOptions& options);

/// Reads, measures, draws and writes. Throws argument_error (e.g. --worst without a
/// tolerance), io_error (unreadable input, nothing to draw, unwritable output).
RenderResult render(const RenderOptions& options);

/// The verdict and the ranked sites, as `trisnap assess` prints them (or why nothing was measured).
std::string summarise(const RenderResult& result);

} // namespace trisnap::render
