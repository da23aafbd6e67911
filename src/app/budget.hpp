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

/// Sets GDAL's caches (OGR_SQLITE_CACHE, GDAL_CACHEMAX) and the OSM driver's node index
/// (OSM_MAX_TMPFILE_SIZE, CPL_TMPDIR = the work directory) within the budget, unless the user set
/// them (environment or --config KEY VALUE).
void apply_gdal_budget(const RunBudget& budget);

/// What the limit holds besides the tiles: the process before any tile (measured when the
/// tiles start) plus this margin for GDAL's caches and the run's buffers.
std::uint64_t reserved_margin(const RunBudget& budget);

} // namespace trisnap
