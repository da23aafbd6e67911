#pragma once
// Plain configuration structs. Resolution order: defaults < `--config FILE.toml` < flags.
// Every field has the same name in TOML ([section] key) and on the command line
// (--key-with-dashes); configs/README.md documents each one.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace trisnap {

/// [snap]: what the engine does (see core/snap.hpp SnapOptions for the exact meaning).
struct SnapConfig {
    std::optional<double> tolerance;   ///< layer units; required (here or as tolerance_m)
    std::optional<double> tolerance_m; ///< metres, geographic CRS only; converted at mean latitude
    double edge_separation = 0.5;      ///< vertex-edge separation as a factor of the tolerance
    double sliver_factor = 1.0;        ///< sliver apex snaps when <= factor x tolerance; 0 = off
    double grid = 0.0;                 ///< output grid step (0 = none), <= tolerance / 4
    double max_drift_factor = 2.0;     ///< report vertices moved further than factor x tolerance
    std::int64_t max_operations = 0;   ///< engine operation cap; 0 = automatic
};

/// [run]: how the run uses the machine.
struct RunConfig {
    int threads = 0; ///< worker threads for GDAL and oneTBB; 0 = all cores
    /// Bytes the whole process may hold (0 = unset: in memory when the layer's estimate fits in
    /// half of the machine's memory, else out of core under that half). TOML: "2GiB" or bytes.
    std::uint64_t memory_limit = 0;
    /// Write the output even when snapping drops more than 10 % of the features (or any, with a
    /// tolerance in degrees above the warning threshold); false: stop before writing (exit 2).
    bool allow_collapse = false;
    /// A tile whose engine fails (an exception inside CGAL or the snapper): "stop" ends the run
    /// (exit 1, nothing written); "skip" retries it merged with its neighbours and, when that
    /// fails too, reports its features (problem 303, not written) and goes on.
    std::string on_error = "stop";
};

/// [tiling]: how a layer is cut into tiles (see stitch/tiled_snap.hpp TilingOptions).
struct TilingConfig {
    double size = 0.0;                  ///< > 0: regular tiles of this side (layer units); 0: balanced
    std::int64_t vertex_budget = 50000; ///< balanced tiles hold at most this many input vertices
    double halo = 32.0;                 ///< halo width as a factor of the tolerance (>= 2)
    int max_growth = 0;                 ///< times a tile's halo may double when a cascade reaches its core (0: no test)
    bool no_tiles = false;              ///< one tile: the whole layer in one triangulation
};

struct Config {
    SnapConfig snap;
    RunConfig run;
    TilingConfig tiling;
};

/// The built-in defaults (taken from the engine's SnapOptions so they cannot drift apart).
Config default_config();

/// Overlays the keys present in `path` on `config`. Throws config_error (file, line, key) for
/// unknown keys, wrong types, integers that do not fit their key, and for a path that is
/// missing, unreadable, a directory or a device, larger than 1 MiB or malformed.
void load_config_file(const std::string& path, Config& config);

/// The same for TOML text already in memory; `path` only names it in errors.
void load_config_text(std::string_view text, const std::string& path, Config& config);

/// The resolved configuration as a TOML document (unset optionals are left out).
std::string to_toml(const Config& config);

/// Checks ranges; returns "" when usable, else a one-line reason naming the key.
std::string check_config(const Config& config);

} // namespace trisnap
