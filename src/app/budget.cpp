#include "app/budget.hpp"

#include "app/memory.hpp"
#include "app/work_dir.hpp"
#include "io/dataset.hpp"

#include <cpl_conv.h>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <thread>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;

// Bytes of the input's files: the path and its siblings of the same stem (a Shapefile's
// .shp/.dbf/.shx), without opening it.
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

// The in-memory run's peak: the process (~100 MiB), the work files held in memory (features,
// buckets and results: about 4x the input's bytes for GeoPackage/Shapefile/FlatGeobuf, 40x for
// a compressed .osm.pbf), and the tiles in flight (2 per thread at the vertex budget).
std::uint64_t estimate(const SnapArgs& args, const Config& config, unsigned threads)
{
    const std::uint64_t in = input_bytes(args.input);
    const double factor = is_osm_path(args.input) ? 40.0 : 4.0;
    const double tiles = 2.0 * threads * static_cast<double>(config.tiling.vertex_budget) * 1100.0;
    return static_cast<std::uint64_t>(100.0 * k_mib + factor * static_cast<double>(in) + tiles);
}

void set_default(const char* key, const std::string& value)
{
    if (!CPLGetConfigOption(key, nullptr)) {
        CPLSetConfigOption(key, value.c_str());
    }
}

} // namespace

RunBudget choose_budget(const SnapArgs& args, const Config& config)
{
    RunBudget b;
    const unsigned threads = config.run.threads > 0 ? static_cast<unsigned>(config.run.threads)
                                                    : std::max(1u, std::thread::hardware_concurrency());
    b.estimate = estimate(args, config, threads);
    b.resume = args.resume;
    if (config.run.memory_limit > 0) {
        b.on_disk = true;
        b.memory_limit = config.run.memory_limit;
        b.reason = "--memory-limit " + format_size(b.memory_limit);
    } else {
        const std::uint64_t half = physical_memory() / 2;
        b.on_disk = b.estimate > half;
        b.memory_limit = b.on_disk ? half : 0;
        b.reason = fmt::format("estimate {} {} half of the memory ({})", format_size(b.estimate),
                               b.on_disk ? ">" : "<=", format_size(half));
    }
    if (!args.work_dir.empty() || args.resume) {
        b.on_disk = true;
    }
    if (b.on_disk) {
        b.work_dir = args.work_dir.empty() ? default_work_dir(args.output) : args.work_dir;
    }
    return b;
}

std::uint64_t reserved_margin(const RunBudget& budget)
{
    if (budget.memory_limit == 0) {
        return 0;
    }
    // GDAL's SQLite page cache and block cache (each at most 1/16 of the limit, see below), the
    // bucket and merge buffers (at most 1/8), and slack for the allocator.
    return budget.memory_limit / 4 + 16 * k_mib;
}

void apply_gdal_budget(const RunBudget& budget)
{
    if (budget.memory_limit > 0) {
        const std::uint64_t cache_mb = std::clamp<std::uint64_t>(budget.memory_limit / 16 / k_mib, 4, 256);
        set_default("OGR_SQLITE_CACHE", std::to_string(cache_mb));
        set_default("GDAL_CACHEMAX", std::to_string(cache_mb));
        set_default("OSM_MAX_TMPFILE_SIZE", std::to_string(std::clamp<std::uint64_t>(budget.memory_limit / 4 / k_mib, 16, 1024)));
    }
    if (budget.on_disk) {
        set_default("CPL_TMPDIR", budget.work_dir);
    }
}

} // namespace trisnap
