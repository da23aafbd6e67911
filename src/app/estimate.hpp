#pragma once
// The one estimate of a `trisnap snap` run: peak memory and time with the run's settings (tiled
// or --no-tiles, threads, --memory-limit, vertex budget). `info`, `validate` and the memory
// budget (in memory or out of core) all call estimate_run(). Calibrated on ../shared/data: the
// table of measured against estimated figures is in bench/README.md ("Estimates").
#include "config/config.hpp"

#include <cstdint>
#include <string>

namespace trisnap {

/// What is known of the layer before the run.
struct EstimateInput {
    std::uint64_t input_bytes = 0; ///< the input's files (a Shapefile's .shp+.dbf+.shx)
    bool osm = false;              ///< a compressed .osm.pbf/.osm (the driver rebuilds geometries)
    std::int64_t vertices = -1;    ///< the layer's vertices after filters; -1: not counted
    std::int64_t features = -1;    ///< the layer's features after filters; -1: not known
};

/// The run's settings that change its cost.
struct EstimateSettings {
    bool tiled = true;
    unsigned threads = 1;
    std::uint64_t memory_limit = 0; ///< out of core under this many bytes; 0: in memory
    std::int64_t vertex_budget = 50000;
};

struct RunEstimate {
    std::int64_t vertices = 0;     ///< counted, or bounded from the input's size
    bool vertices_counted = false;
    std::uint64_t peak_bytes = 0;  ///< peak resident memory of the process
    double cpu_seconds = 0.0;      ///< user + system
    double wall_seconds = 0.0;
};

/// The settings of a run from its resolved configuration (threads 0 = all cores).
EstimateSettings estimate_settings(const Config& config);

/// Bytes of the input's files (0 for a connection string or a virtual path), without opening it.
std::uint64_t input_bytes(const std::string& input);

/// The input for estimate_run(): the files' size and kind, the layer's counts (-1: unknown).
EstimateInput estimate_input(const std::string& input, std::int64_t vertices, std::int64_t features);

/// The vertices when none were counted: the most the input's files can hold (uncompressed
/// formats store 16 bytes or more per 2D vertex), or for an .osm.pbf a typical count of its
/// multipolygons per byte (the shared extracts hold half to twice that: not a bound).
std::int64_t vertices_bound(const EstimateInput& in);

RunEstimate estimate_run(const EstimateInput& in, const EstimateSettings& settings);

/// "~310 MiB peak, ~4.1 s CPU, ~4.1 s wall (411137 vertices, 2 threads, tiled)".
std::string describe_estimate(const RunEstimate& e, const EstimateSettings& settings);

} // namespace trisnap
