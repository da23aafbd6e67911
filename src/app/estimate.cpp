#include "app/estimate.hpp"

#include "config/size.hpp"
#include "io/dataset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <thread>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

// Calibration (bench/README.md "Estimates": `trisnap snap` on every shared data set, 2 threads,
// tiled and --no-tiles, peak RSS and user+sys from /usr/bin/time -v). The memory constants are
// 2026-11-23's (conservative: since the lean engine they overestimate large layers up to 3.5x,
// and a linear model that stays above the hard polygons' tiled peaks cannot do better); the time
// constants 2026-11-28's, refitted after the lean engine made runs 3-5x faster than they said.
constexpr double k_base_bytes = 58.0 * 1024 * 1024; // the process with GDAL, PROJ and an empty layer
constexpr double k_held_per_vertex = 440.0;         // features, buckets and results kept for the write
constexpr double k_triangulation_per_vertex = 600.0; // a tile's triangulation and snap state
constexpr double k_osm_bytes_factor = 40.0;         // the OSM driver's node index and relation buffers
constexpr double k_base_seconds = 0.2;              // start (GDAL, PROJ, oneTBB), open, write an empty layer
constexpr double k_seconds_per_vertex = 4.5e-6;     // read, triangulate, snap, write
constexpr double k_seconds_per_feature = 10e-6;     // read, attribute copy, write, R-tree entry
constexpr double k_osm_seconds_per_byte = 0.3e-6;   // decode the whole .pbf (every layer's nodes)
constexpr double k_out_of_core_slowdown = 1.15;     // spool and merge through files
constexpr double k_uncompressed_bytes_per_vertex = 16.0; // one 2D vertex in WKB, Shapefile, FlatGeobuf
constexpr double k_osm_vertices_per_byte = 0.055;   // typical: 0.025 (Helsinki) to 0.12 (Monaco 2020)
constexpr double k_vertices_per_feature = 10.0;     // when only vertices are known (OSM areas: ~9)

// Vertices in triangulations at once: all of them with one tile, else one tile of the budget
// per thread (tiles are cut at half the budget to the budget).
double vertices_in_flight(double vertices, const EstimateSettings& s)
{
    if (!s.tiled) {
        return vertices;
    }
    const double budget = static_cast<double>(std::max<std::int64_t>(1, s.vertex_budget));
    return std::min(vertices, budget * std::max(1u, s.threads));
}

// Threads busy at once: tiles run in parallel, the read and the write do not.
double parallelism(double vertices, const EstimateSettings& s)
{
    if (!s.tiled || s.threads <= 1) {
        return 1.0;
    }
    const double budget = static_cast<double>(std::max<std::int64_t>(1, s.vertex_budget));
    const double tiles = std::max(1.0, vertices / budget);
    const double busy = std::min(tiles, static_cast<double>(s.threads));
    return 1.0 + 0.5 * (busy - 1.0); // about half the work is in the tiles
}

} // namespace

EstimateSettings estimate_settings(const Config& config)
{
    EstimateSettings s;
    s.tiled = !config.tiling.no_tiles;
    s.threads = config.run.threads > 0 ? static_cast<unsigned>(config.run.threads)
                                       : std::max(1u, std::thread::hardware_concurrency());
    s.memory_limit = config.run.memory_limit;
    s.vertex_budget = config.tiling.vertex_budget;
    return s;
}

std::uint64_t input_bytes(const std::string& input)
{
    std::error_code ec;
    const fs::path p(input);
    if (!fs::is_regular_file(p, ec)) {
        return 0;
    }
    std::uint64_t n = fs::file_size(p, ec);
    if (p.extension() == ".shp") {
        for (const char* ext : {".dbf", ".shx"}) {
            fs::path sibling = p;
            sibling.replace_extension(ext);
            n += fs::is_regular_file(sibling, ec) ? fs::file_size(sibling, ec) : 0;
        }
    }
    return n;
}

EstimateInput estimate_input(const std::string& input, std::int64_t vertices, std::int64_t features)
{
    EstimateInput in;
    in.input_bytes = input_bytes(input);
    in.osm = is_osm_path(input);
    in.vertices = vertices;
    in.features = features;
    return in;
}

std::int64_t vertices_bound(const EstimateInput& in)
{
    const auto bytes = static_cast<double>(in.input_bytes);
    if (in.osm) {
        return static_cast<std::int64_t>(bytes * k_osm_vertices_per_byte);
    }
    return static_cast<std::int64_t>(bytes / k_uncompressed_bytes_per_vertex);
}

RunEstimate estimate_run(const EstimateInput& in, const EstimateSettings& settings)
{
    RunEstimate e;
    e.vertices_counted = in.vertices >= 0;
    e.vertices = e.vertices_counted ? in.vertices : vertices_bound(in);
    const auto v = static_cast<double>(e.vertices);
    const double features = in.features >= 0 ? static_cast<double>(in.features) : v / k_vertices_per_feature;
    const double osm_bytes = in.osm ? static_cast<double>(in.input_bytes) : 0.0;
    double peak = k_base_bytes + k_held_per_vertex * v + k_triangulation_per_vertex * vertices_in_flight(v, settings) +
                  k_osm_bytes_factor * osm_bytes;
    double cpu = k_base_seconds + k_seconds_per_vertex * v + k_seconds_per_feature * features +
                 k_osm_seconds_per_byte * osm_bytes;
    if (settings.memory_limit > 0) {
        peak = std::min(peak, static_cast<double>(settings.memory_limit));
        cpu *= k_out_of_core_slowdown;
    }
    e.peak_bytes = static_cast<std::uint64_t>(peak);
    e.cpu_seconds = cpu;
    e.wall_seconds = cpu / parallelism(v, settings);
    return e;
}

std::string describe_estimate(const RunEstimate& e, const EstimateSettings& settings)
{
    const std::string vertices = e.vertices_counted ? fmt::format("{} vertices", e.vertices)
                                                    : fmt::format("~{} vertices from the input's size", e.vertices);
    const std::string mode = settings.memory_limit > 0 ? "out of core under " + format_size(settings.memory_limit)
                                                       : (settings.tiled ? "tiled" : "--no-tiles");
    return fmt::format("~{} peak, ~{:.1f} s CPU, ~{:.1f} s wall ({}, {} thread{}, {})", format_size(e.peak_bytes),
                       e.cpu_seconds, e.wall_seconds, vertices, settings.threads, settings.threads == 1 ? "" : "s", mode);
}

} // namespace trisnap
