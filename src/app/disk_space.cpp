#include "app/disk_space.hpp"

#include "app/estimate.hpp"
#include "config/size.hpp"
#include "io/dataset.hpp"
#include "io/io_error.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <string>

namespace trisnap {
namespace {

constexpr std::uint64_t k_mib = 1024 * 1024;
// Room beyond the estimates: the records and the problem log, the merge files, the slack of a
// file system near full.
constexpr std::uint64_t k_margin = 64 * k_mib;
// features.bin per byte of input (of the layers' share of it), below the lowest measured on the
// shared data sets (bench/README.md, "Work files": 0.18 for a GeoPackage, Andorra's buildings;
// 0.47 for an .osm.pbf, Helsinki's multipolygons): a floor, so that the check before the read
// refuses only a disk that is surely too small; the check after it is exact.
constexpr double k_spool_per_input_byte = 0.15;
constexpr double k_spool_per_osm_byte = 0.4;

// The input layers' share of the file's features (1 for one layer, or when a count is unknown).
double layer_share(const Plan& plan)
{
    double selected = 0;
    for (std::int64_t n : plan.feature_counts) {
        if (n < 0) {
            return 1.0;
        }
        selected += static_cast<double>(n);
    }
    double all = 0;
    for (int i = 0; i < plan.dataset->GetLayerCount(); ++i) {
        const GIntBig n = plan.dataset->GetLayer(i)->GetFeatureCount(FALSE);
        if (n < 0) {
            return 1.0;
        }
        all += static_cast<double>(n);
    }
    return all > 0 ? std::min(1.0, selected / all) : 1.0;
}

[[noreturn]] void not_enough(const WorkDir& work, std::uint64_t need, const std::string& what, std::uint64_t free)
{
    throw io_error(work.path(), "",
                   fmt::format("not enough free disk for the work files: about {} {}, {} are free; free some space "
                               "there or give --work-dir on a larger disk",
                               format_size(need), what, format_size(free)));
}

} // namespace

std::uint64_t free_disk(const tiling::WorkStore& store)
{
    if (const char* fake = std::getenv("TRISNAP_TEST_FREE_DISK"); fake != nullptr && *fake != '\0') {
        return std::stoull(fake);
    }
    return store.free_space();
}

std::uint64_t work_files_floor(const Plan& plan)
{
    const double ratio = is_osm_path(plan.input_path) ? k_spool_per_osm_byte : k_spool_per_input_byte;
    const double features = ratio * static_cast<double>(input_bytes(plan.input_path)) * layer_share(plan);
    return 3 * static_cast<std::uint64_t>(features) + k_margin;
}

void check_disk_before_read(WorkDir& work, const Plan& plan)
{
    if (!work.on_disk()) {
        return;
    }
    const std::uint64_t need = work_files_floor(plan);
    const std::uint64_t free = free_disk(work.store());
    if (free < need) {
        const std::string what = fmt::format("are needed at least for an input of {}", format_size(input_bytes(plan.input_path)));
        not_enough(work, need, what, free);
    }
}

// The buckets hold about features.bin again (a feature cut by seams is in several; a plan of
// one leaf keeps none, and this then asks for more than it needs), the tile results as much again.
void check_disk_after_read(WorkDir& work, const stitch::SpoolMeta& meta)
{
    if (!work.on_disk()) {
        return;
    }
    const std::uint64_t need = 2 * work.store().total_bytes() + k_margin;
    const std::uint64_t free = free_disk(work.store());
    if (free < need) {
        not_enough(work, need, fmt::format("more are needed for {} features", meta.spooled), free);
    }
}

} // namespace trisnap
