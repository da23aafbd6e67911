#pragma once
// The options shared by `snap` and `validate`, as parsed by CLI11 (no I/O here), and their
// resolution into a Config: defaults < --settings FILE.toml < flags.
#include "config/config.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace trisnap {

struct SnapArgs {
    std::string input;
    std::string output;
    /// --layer, repeatable: the layers snapped together in one triangulation, each written to
    /// its own output layer (none: the only polygon/line layer).
    std::vector<std::string> layers;
    std::string report;
    std::string format;
    std::string new_layer_name; ///< -nln
    std::string where;
    std::optional<std::string> bbox; ///< given (even empty) or not
    std::string settings_file; ///< --settings (also --config FILE.toml)
    std::string problems_layer; ///< --problems-layer FILE.gpkg|.geojson
    std::string progress = "auto";
    std::vector<std::string> layer_options;   ///< --lco K=V
    std::vector<std::string> dataset_options; ///< --dsco K=V
    std::vector<std::string> open_options;    ///< --oo K=V, for the input
    std::string select;                       ///< --select f1,f2: the fields written
    std::optional<double> tolerance;
    std::optional<double> tolerance_m;
    std::optional<double> grid;
    std::optional<double> edge_separation;
    std::optional<double> sliver_factor;
    std::optional<double> max_drift_factor;
    std::optional<std::int64_t> max_operations;
    std::optional<int> threads;
    std::optional<double> tile_size;
    std::optional<std::int64_t> tile_vertex_budget;
    std::optional<double> halo;
    std::optional<int> halo_max_growth;
    std::optional<std::string> memory_limit;
    std::optional<std::string> on_error; ///< --on-error stop|skip ([run] on_error)
    std::string work_dir;
    bool resume = false;
    bool no_tiles = false;
    bool overwrite = false;
    bool update = false;         ///< --update: write the layer into an existing OUT
    bool append = false;         ///< --append: add to OUT's layer of that name
    bool allow_collapse = false; ///< --allow-collapse, --force ([run] allow_collapse)
    bool strict = false;
    bool print_config = false;
    bool json_progress = false;
    bool skip_failures = false; ///< -skipfailures: what trisnap always does (problem 902)
    int verbose = 0;
    int quiet = 0;
};

/// Declares the snap/validate options on `command`; values land in `args`.
void add_snap_options(CLI::App& command, SnapArgs& args, bool needs_output);

/// The groups of options add_snap_options declares, for the commands that take some of them
/// (plan, stitch): IN, --layer, --oo, --where, --bbox;
void add_input_options(CLI::App& command, SnapArgs& args);
/// OUT, -f, --lco, --dsco, -nln, --select, --overwrite, --update, --append, --skipfailures, --report, --problems-layer,
/// --allow-collapse;
void add_output_options(CLI::App& command, SnapArgs& args, bool writes);
/// --tolerance, --tolerance-m and the engine settings;
void add_engine_options(CLI::App& command, SnapArgs& args);
/// --settings, --print-config;
void add_settings_options(CLI::App& command, SnapArgs& args);
/// --tile-size, --tile-vertex-budget, --halo, --halo-max-growth, --no-tiles;
void add_tiling_options(CLI::App& command, SnapArgs& args);
/// --progress, --json-progress, -v, -q.
void add_logging_options(CLI::App& command, SnapArgs& args);

/// Defaults, then the --settings file, then flags. Throws config_error / argument_error.
Config resolve_config(const SnapArgs& args);

/// Lowers config.run.threads to the cores available, with one warning, when it asks for more.
void clamp_threads(Config& config);

/// The common start of snap and validate: logging set up, config resolved. With
/// --print-config it prints the resolved TOML and returns nothing (the command is done).
std::optional<Config> start_snap_command(const SnapArgs& args);

/// xmin,ymin,xmax,ymax; throws argument_error.
std::vector<double> parse_bbox(const std::string& text);

/// Refuses a --report FILE whose directory does not exist (argument_error).
void check_report_path(const std::string& path);

/// Throws argument_error naming `flag` unless every item is KEY=VALUE.
void check_key_values(const std::vector<std::string>& items, const std::string& flag);

/// "a,b , c" -> {"a", "b", "c"}; empty items dropped.
std::vector<std::string> split_list(const std::string& text);

} // namespace trisnap
