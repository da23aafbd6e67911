// The tiled run's state, shared by tiled_snap.cpp (scheduling, stitch, output) and
// tile_retry.cpp (what happens to a tile whose engine failed). Not part of the interface.
#pragma once

#include "stitch/tile_run.hpp"
#include "stitch/tiled_snap.hpp"

#include <tbb/info.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace trisnap::stitch {

struct TiledRun::Impl {
    Impl(tiling::WorkStore& s, const SnapOptions& o, const TilingOptions& t, const ScheduleOptions& sc)
        : store(s), options(o), tiling(t), schedule(sc)
    {
    }
    int threads() const { return schedule.threads > 0 ? schedule.threads : tbb::info::default_concurrency(); }
    void save_groups();
    void run_groups(std::vector<std::size_t> pending, const TileProgress& progress, bool retry = true);
    std::vector<std::pair<std::size_t, std::string>> run_once(std::vector<std::size_t> pending, const TileProgress& progress);
    std::string run_one(const TileRunner& runner, std::size_t group, const std::function<void(std::size_t, std::size_t)>& on_progress,
                        TileInputMode mode = TileInputMode::cut);
    void retry_whole(const std::vector<std::pair<std::size_t, std::string>>& failed, const std::string& tried);
    void retry_merged(const std::vector<std::pair<std::size_t, std::string>>& failed, const TileProgress& progress);
    std::vector<std::uint64_t> dropped_ranks() const;
    std::uint64_t max_tile_vertices() const;

    tiling::WorkStore& store;
    SnapOptions options;
    TilingOptions tiling;
    ScheduleOptions schedule;
    SpoolMeta meta;
    TileLayout layout;
    Groups groups;
    std::uint64_t planned_budget = 0; ///< the tile vertex budget plan() planned with; 0: it took an earlier run's plan
    std::vector<std::pair<std::uint64_t, Problem>> notes;
    StitchStats stats;
};

} // namespace trisnap::stitch
