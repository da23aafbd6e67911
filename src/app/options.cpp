#include "app/options.hpp"

#include "app/command.hpp"
#include "config/errors.hpp"
#include "config/size.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace trisnap {

void add_input_options(CLI::App& c, SnapArgs& a)
{
    c.add_option("IN", a.input, "input vector dataset or GDAL connection string (GPKG, Shapefile, FlatGeobuf, "
                                "GeoJSON, .osm.pbf, /vsizip/..., PG:...)");
    c.add_option("--layer", a.layers, "input layer (default: the only polygon/line layer); repeat it to snap "
                                      "several layers together, each to its own output layer")
        ->allow_extra_args(false); // one name per --layer: `--layer a IN OUT` must not take IN and OUT
    c.add_option("--oo", a.open_options, "input open option K=V (repeatable), as ogr2ogr -oo");
    c.add_option("--where", a.where, "attribute filter (OGR SQL WHERE clause; also -where)");
    c.add_option("--bbox", a.bbox, "spatial filter xmin,ymin,xmax,ymax in layer units (also -spat xmin ymin xmax ymax)");
}

void add_output_options(CLI::App& c, SnapArgs& a, bool writes)
{
    c.add_option("OUT", a.output, writes ? "output dataset; format from the extension or -f; - for stdout (GeoJSON, "
                                           "GeoJSONSeq or FlatGeobuf)"
                                         : "output dataset (checked, not written)");
    c.add_option("-f,--format", a.format, "output GDAL driver short name (GPKG, \"ESRI Shapefile\", FlatGeobuf, GeoJSON)");
    c.add_option("--lco", a.layer_options, "layer creation option K=V (repeatable), as ogr2ogr -lco");
    c.add_option("--dsco", a.dataset_options, "dataset creation option K=V (repeatable), as ogr2ogr -dsco");
    c.add_option("--nln", a.new_layer_name, "output layer name (also -nln; default: the input layer's)");
    c.add_option("--select", a.select, "write only these fields, comma-separated (also -select)");
    c.add_flag("--overwrite", a.overwrite, "replace OUT's layer in a GPKG/SQLite file (its other layers stay), else "
                                           "OUT itself, and --problems-layer, if they exist (also -overwrite)");
    c.add_flag("--update", a.update, "write the layer into an existing GPKG/SQLite OUT beside its other layers "
                                     "(also -update)");
    c.add_flag("--append", a.append, "add the features to OUT's layer of that name (GPKG/SQLite; also -append)");
    c.add_flag("--skipfailures", a.skip_failures, "accepted for ogr2ogr: features the driver refuses are always "
                                                  "skipped and reported (problem 902)");
    c.add_option("--report", a.report, "write the run manifest and problems as JSON to FILE");
    c.add_option("--problems-layer", a.problems_layer, "write the problems as points to FILE.gpkg or FILE.geojson");
    c.add_flag("--allow-collapse,--force", a.allow_collapse, "write OUT even when snapping drops more than 10 % of "
                                                         "the features, or any with a tolerance in degrees >= 0.001 "
                                                         "([run] allow_collapse)");
}

void add_engine_options(CLI::App& c, SnapArgs& a)
{
    c.add_option("--tolerance", a.tolerance, "snap tolerance t in layer units ([snap] tolerance)");
    c.add_option("--tolerance-m", a.tolerance_m, "tolerance in metres; converted at the layer's mean latitude on a geographic CRS ([snap] tolerance_m)");
    c.add_option("--grid", a.grid, "output grid step, <= t/4; 0 = none ([snap] grid)");
    c.add_option("--edge-separation", a.edge_separation, "vertex-edge separation factor of t, (0, 1] ([snap] edge_separation)");
    c.add_option("--sliver-factor", a.sliver_factor, "sliver apex snap distance factor of t; 0 = off ([snap] sliver_factor)");
    c.add_option("--max-drift-factor", a.max_drift_factor, "report moves beyond this factor of t ([snap] max_drift_factor)");
    c.add_option("--max-operations", a.max_operations, "engine operation cap; 0 = automatic ([snap] max_operations)");
}

void add_settings_options(CLI::App& c, SnapArgs& a)
{
    c.add_option("--settings", a.settings_file, "TOML settings file (see configs/README.md); --config FILE.toml works too");
    c.add_flag("--print-config", a.print_config, "print the resolved configuration as TOML and exit");
}

void add_tiling_options(CLI::App& c, SnapArgs& a)
{
    c.add_option("--tile-size", a.tile_size, "regular square tiles of this side in layer units; 0 = balanced by vertex count ([tiling] size)");
    c.add_option("--tile-vertex-budget", a.tile_vertex_budget, "balanced tiles hold at most this many input vertices ([tiling] vertex_budget)");
    c.add_option("--halo", a.halo, "tile halo width as a factor of the tolerance, >= 2 ([tiling] halo)");
    c.add_option("--halo-max-growth", a.halo_max_growth, "times a tile's halo may double when a snap cascade reaches its core ([tiling] max_growth)");
    c.add_flag("--no-tiles", a.no_tiles, "one triangulation for the whole layer ([tiling] no_tiles)");
}

void add_logging_options(CLI::App& c, SnapArgs& a)
{
    c.add_option("--progress", a.progress, "progress bar: auto (TTY only), always, never")
        ->check(CLI::IsMember({"auto", "always", "never"}));
    c.add_flag("--json-progress", a.json_progress, "progress as JSON lines on stderr");
    c.add_flag("-v,--verbose", a.verbose, "more log output (repeatable)");
    c.add_flag("-q,--quiet", a.quiet, "only errors; no summary");
}

namespace {

void add_run_options(CLI::App& c, SnapArgs& a)
{
    add_settings_options(c, a);
    c.add_flag("--strict", a.strict, "exit with code 3 when any problem is reported");
    c.add_option("--threads", a.threads, "worker threads for GDAL and oneTBB; 0 = all cores ([run] threads)");
    add_tiling_options(c, a);
    c.add_option("--memory-limit", a.memory_limit, "out of core under this much memory, e.g. 2GiB, 512MiB ([run] memory_limit)");
    c.add_option("--on-error", a.on_error, "when a tile's engine fails: stop the run, or skip: retry it merged with its "
                                           "neighbours, then report its features (problem 303) and go on ([run] on_error)")
        ->check(CLI::IsMember({"stop", "skip"}));
    c.add_option("--work-dir", a.work_dir, "directory for the work files of an out-of-core run (default: .OUT.trisnap-work beside OUT)");
    c.add_flag("--resume", a.resume, "continue the run whose work directory is there (same command and input)");
    add_logging_options(c, a);
}

template <typename T, typename U>
void overlay(const std::optional<T>& flag, U& field)
{
    if (flag) field = *flag;
}

} // namespace

void add_snap_options(CLI::App& command, SnapArgs& args, bool needs_output)
{
    add_input_options(command, args);
    add_output_options(command, args, needs_output);
    add_engine_options(command, args);
    add_run_options(command, args);
}

Config resolve_config(const SnapArgs& args)
{
    if (args.tolerance && args.tolerance_m) throw argument_error("give --tolerance or --tolerance-m, not both");
    Config config = default_config();
    if (!args.settings_file.empty()) {
        load_config_file(args.settings_file, config);
        if (std::string reason = check_config(config); !reason.empty()) {
            throw config_error(args.settings_file, 0, "", reason);
        }
    }
    overlay(args.tolerance, config.snap.tolerance);
    overlay(args.tolerance_m, config.snap.tolerance_m);
    if (args.tolerance) config.snap.tolerance_m.reset(); // a flag beats the other form in a file
    if (args.tolerance_m && !args.tolerance) config.snap.tolerance.reset();
    overlay(args.grid, config.snap.grid);
    overlay(args.edge_separation, config.snap.edge_separation);
    overlay(args.sliver_factor, config.snap.sliver_factor);
    overlay(args.max_drift_factor, config.snap.max_drift_factor);
    overlay(args.max_operations, config.snap.max_operations);
    overlay(args.threads, config.run.threads);
    if (args.allow_collapse) {
        config.run.allow_collapse = true;
    }
    if (args.memory_limit) {
        config.run.memory_limit = parse_size(*args.memory_limit, "--memory-limit");
    }
    overlay(args.on_error, config.run.on_error);
    overlay(args.tile_size, config.tiling.size);
    overlay(args.tile_vertex_budget, config.tiling.vertex_budget);
    overlay(args.halo, config.tiling.halo);
    overlay(args.halo_max_growth, config.tiling.max_growth);
    if (args.no_tiles) config.tiling.no_tiles = true;
    if (args.no_tiles && args.tile_size) throw argument_error("give --tile-size or --no-tiles, not both");
    if (std::string reason = check_config(config); !reason.empty()) throw argument_error(reason);
    return config;
}

std::vector<double> parse_bbox(const std::string& text)
{
    std::vector<double> values;
    std::istringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v))
            throw argument_error("--bbox: '" + item + "' is not a number (expected xmin,ymin,xmax,ymax)");
        values.push_back(v);
    }
    if (values.size() != 4 || values[0] >= values[2] || values[1] >= values[3])
        throw argument_error("--bbox must be xmin,ymin,xmax,ymax with xmin < xmax and ymin < ymax, got '" + text + "'");
    return values;
}

void check_report_path(const std::string& path)
{
    if (path.empty()) {
        return;
    }
    const std::filesystem::path p(path);
    const auto parent = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(parent)) {
        throw argument_error("--report " + path + ": the directory " + parent.string() + " does not exist");
    }
}

void check_key_values(const std::vector<std::string>& items, const std::string& flag)
{
    for (const std::string& item : items) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0) {
            throw argument_error(flag + " '" + item + "': expected KEY=VALUE");
        }
    }
}

std::vector<std::string> split_list(const std::string& text)
{
    std::vector<std::string> items;
    std::istringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        const auto first = item.find_first_not_of(' ');
        const auto last = item.find_last_not_of(' ');
        if (first != std::string::npos) {
            items.push_back(item.substr(first, last - first + 1));
        }
    }
    return items;
}

void clamp_threads(Config& config)
{
    const int cores = available_cores();
    if (config.run.threads <= cores) {
        return;
    }
    // More threads than cores only adds contention: 10000 spawned thousands and took minutes.
    spdlog::warn("threads {} is more than the {} cores available; using {}", config.run.threads, cores, cores);
    config.run.threads = cores;
}

std::optional<Config> start_snap_command(const SnapArgs& args)
{
    setup_logging(args.verbose, args.quiet);
    Config config = resolve_config(args);
    clamp_threads(config);
    if (!args.print_config) return config;
    std::cout << to_toml(config);
    return std::nullopt;
}

} // namespace trisnap
