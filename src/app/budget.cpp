#include "app/budget.hpp"

#include "app/estimate.hpp"
#include "app/memory.hpp"
#include "app/work_dir.hpp"
#include "io/gpkg_rtree.hpp"

#include <cpl_conv.h>
#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace trisnap {
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;

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
    // Before the input is opened: its vertices are bounded from its size (see estimate.hpp).
    const EstimateInput input = estimate_input(args.input, -1, -1);
    b.estimate = estimate_run(input, estimate_settings(config)).peak_bytes;
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
    return reserved_margin(budget.memory_limit);
}

std::uint64_t reserved_margin(std::uint64_t memory_limit)
{
    if (memory_limit == 0) {
        return 0;
    }
    // GDAL's block cache (at most 1/16 of the limit, see below) and SQLite's page caches (its
    // default, ~2 MB a connection), the bucket and merge buffers (at most 1/8), and slack for
    // the allocator (a second reader's sample during the read, 1/16, among it).
    return memory_limit / 4 + 16 * k_mib;
}

std::size_t sample_vertices(std::uint64_t memory_limit)
{
    return memory_limit ? static_cast<std::size_t>(memory_limit / 16 / 16) : std::size_t{16} << 20;
}

std::size_t fid_buffer(std::uint64_t memory_limit)
{
    return memory_limit ? static_cast<std::size_t>(memory_limit / 16 / 8) : std::numeric_limits<std::size_t>::max();
}

std::size_t index_boxes(std::uint64_t memory_limit)
{
    return memory_limit ? static_cast<std::size_t>(memory_limit / 32 / sizeof(RtreeEntry)) : std::size_t{1} << 26;
}

std::uint64_t gdal_cache_bytes(std::uint64_t memory_limit)
{
    return std::clamp<std::uint64_t>(memory_limit / 16 / k_mib, 4, 256) * k_mib;
}

std::uint64_t HeldByLimit::at(std::uint64_t memory_limit) const
{
    const std::uint64_t sample = 16 * std::min<std::uint64_t>(vertices, sample_vertices(memory_limit));
    const std::uint64_t fids = 8 * std::min<std::uint64_t>(features, fid_buffer(memory_limit));
    return sample + fids;
}

// f(L) = fixed + grows.at(L) + L/4 + 16 MiB + tile rises by less than L (its slope is at most
// 1/4 + 3/16), so iterating L <- f(L) from below climbs to the least fixed point.
std::uint64_t smallest_limit(std::uint64_t tried, std::uint64_t held, const HeldByLimit& grows, std::uint64_t tile)
{
    const std::uint64_t fixed = held - std::min(held, grows.at(tried));
    std::uint64_t limit = tried;
    for (int i = 0; i < 200; ++i) {
        const std::uint64_t need = fixed + grows.at(limit) + reserved_margin(limit) + tile;
        if (need <= limit) {
            break;
        }
        limit = need;
    }
    return (limit + k_mib - 1) / k_mib * k_mib;
}

void apply_gdal_budget(const RunBudget& budget)
{
    if (budget.memory_limit > 0) {
        // GDAL's raster block cache is bounded (its default is 5 % of the memory). SQLite's page
        // cache is left at SQLite's default, about 2 MB a connection: OGR_SQLITE_CACHE does not
        // bound it but sets it, and at a sixteenth of the limit each connection (the input's,
        // the second reader's, OUT's) filled up to 128 MiB of pages that a scan in rowid order
        // and rows appended in FID order never read again: 1 M polygons under 2 GiB, peak 474
        // -> 344 MiB, the read 1.60 -> 1.39 s (bench/results/REPORT.md, "SQLite's cache").
        set_default("GDAL_CACHEMAX", std::to_string(gdal_cache_bytes(budget.memory_limit) / k_mib));
        set_default("OSM_MAX_TMPFILE_SIZE", std::to_string(std::clamp<std::uint64_t>(budget.memory_limit / 4 / k_mib, 16, 1024)));
    }
    if (budget.on_disk) {
        set_default("CPL_TMPDIR", budget.work_dir);
    }
}

} // namespace trisnap
