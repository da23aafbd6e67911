#pragma once
// The plan of a snap run: everything that can be checked before reading the data (options,
// config, input layer, filters, tolerance in layer units, output format and path). `validate`
// stops here and prints it; `snap` executes it.
#include "app/options.hpp"
#include "config/config.hpp"
#include "core/snap.hpp"
#include "io/writer.hpp"
#include "stitch/tiled_snap.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace trisnap {

struct Plan {
    Config config;
    GDALDatasetUniquePtr dataset;
    OGRLayer* layer = nullptr;        ///< the first (or only) input layer: the tolerance is resolved on it
    /// Every input layer in --layer order (layers[0] == layer): one engine run, one output
    /// layer each. Several only in the same CRS (from an OSM file: its file is read once per layer).
    std::vector<OGRLayer*> layers;
    std::vector<std::int64_t> feature_counts; ///< per layer, after filters; -1 when unknown
    std::string input_path;
    std::vector<std::string> open_options; ///< --oo, as the input was opened with
    std::string input_driver;
    std::string crs;
    std::int64_t feature_count = -1; ///< after filters; -1 when unknown without a full read
    double tolerance = 0.0;          ///< layer units
    std::string tolerance_note;      ///< how the tolerance was derived
    SnapOptions options;
    WriteOptions write;
    std::string output_driver;
    bool keeps_fids = false;
    std::string bbox;                 ///< --bbox as given ("" = none)
    stitch::TilingOptions tiling;     ///< tile size in layer units, one tile with --no-tiles; threads from [run]
};

/// Checks options and config, opens the input, chooses the layer, applies --where/--bbox,
/// resolves the tolerance and checks the output. Throws argument_error, config_error, io_error.
Plan make_plan(const SnapArgs& args, const Config& config);

/// The input half of make_plan (no output: `trisnap plan`): the layer, its filters, the
/// tolerance in layer units, the engine and tiling options.
Plan make_input_plan(const SnapArgs& args, const Config& config);

/// The engine's options from the settings and the tolerance in layer units; throws
/// argument_error for unusable values.
SnapOptions engine_options(const Config& config, double tolerance);

/// The tiling options from the settings ([tiling], and [run] threads).
stitch::TilingOptions tiling_options(const Config& config);

/// The output layer of input layer `k`: -nln (one layer only), else the input layer's name.
std::string output_layer_name(const Plan& plan, std::size_t k);

/// "layer 'a'", or "layers 'a', 'b'" with several: for messages about the whole input.
std::string layers_label(const Plan& plan);

/// "IN (layer 'a')" or "IN (layers 'a', 'b')": where an error about the whole input happened.
std::string input_label(const Plan& plan);

/// Human-readable plan (the output of `validate`).
void print_plan(const Plan& plan, std::ostream& out);

} // namespace trisnap
