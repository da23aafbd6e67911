#pragma once
// How a snap run uses memory and disk: in memory, or out of core under a limit with its work
// files in a directory. Decided before the input is opened (GDAL's caches and the OSM driver's
// node index are configured from it).
//  - `--memory-limit SIZE` (or [run] memory_limit): out of core under SIZE;
//  - else: in memory when the run's estimate (app/estimate.hpp, with the vertices bounded from
//    the input's size, as nothing is open yet) fits in half of the machine's memory (or its
//    cgroup limit), otherwise out of core under that half;
//  - `--work-dir DIR` or `--resume`: the work files go to a directory whatever the memory.
#include "app/options.hpp"
#include "config/config.hpp"

#include <cstdint>
#include <string>

namespace trisnap {

struct RunBudget {
    bool on_disk = false;           ///< work files in a directory
    std::uint64_t memory_limit = 0; ///< bytes the whole process may hold; 0: not bounded
    std::uint64_t estimate = 0;     ///< the run's estimated peak (bytes), from the input's size
    std::string reason;             ///< why this mode, for the plan and the report
    std::string work_dir;
    bool resume = false;
};

RunBudget choose_budget(const SnapArgs& args, const Config& config);

/// Sets GDAL's raster block cache (GDAL_CACHEMAX) and the OSM driver's node index
/// (OSM_MAX_TMPFILE_SIZE, CPL_TMPDIR = the work directory) within the budget, unless the user set
/// them (environment or --config KEY VALUE). SQLite's page cache keeps SQLite's default.
void apply_gdal_budget(const RunBudget& budget);

/// What the limit holds besides the tiles: the process before any tile (measured when the
/// tiles start) plus this margin for GDAL's caches and the run's buffers.
std::uint64_t reserved_margin(const RunBudget& budget);
std::uint64_t reserved_margin(std::uint64_t memory_limit);

/// Under a limit, the read phase's buffers: the plan's vertex sample (vertices; limit/16 bytes)
/// and the FIDs the uniqueness check sorts in memory at once (limit/16 bytes). A second reader
/// (app/read_phase.cpp) keeps a sample of its own of the same size until its part is appended.
std::size_t sample_vertices(std::uint64_t memory_limit);
std::size_t fid_buffer(std::uint64_t memory_limit);
/// Feature boxes the GeoPackage writer keeps in memory to bulk load OUT's spatial index (24
/// bytes each, io/gpkg_rtree.hpp): 1/32 of a limit, else 2^26; beyond them the boxes are sorted
/// in runs on disk and the same tree is packed from their merge (the same bytes). The in-memory
/// packing holds the boxes about twice over, the on-disk one about twice the budget; that is
/// inside the limit's margin on the tests' layers (their peak stays under it), not a bound
/// proven for every layer.
std::size_t index_boxes(std::uint64_t memory_limit);
std::uint64_t gdal_cache_bytes(std::uint64_t memory_limit);

/// What a layer makes the process hold before any tile beyond what does not depend on the limit:
/// the buffers above, each no larger than the layer fills it.
struct HeldByLimit {
    std::uint64_t vertices = 0;    ///< the layer's engine vertices (the sample holds at most all)
    std::uint64_t features = 0;    ///< its features (the FID buffer holds at most all)
    std::uint64_t at(std::uint64_t memory_limit) const;
};

/// The smallest limit L under which a fresh run leaves `tile` bytes for the tiles: a process that
/// held `held` under the limit `tried` holds held - grows.at(tried) + grows.at(L) under L, beside
/// reserved_margin(L); the least L with L >= that + reserved_margin(L) + tile (a fixed point:
/// the margin and the buffers grow with L), rounded up to a MiB.
std::uint64_t smallest_limit(std::uint64_t tried, std::uint64_t held, const HeldByLimit& grows, std::uint64_t tile);

} // namespace trisnap
