#pragma once
// One tile job: its box R is the core grown by the halo h, grown again to hold both ends of
// every input edge meeting that, plus h (a long edge moves with its far end). Build its input, snap it, and check that no chain of snapping reached from the
// edge of what the tile can see (near the border of R, or beyond) into its core. If one did,
// the core may differ from an untiled run: the halo doubles and the tile runs again (up to
// `max_growth` times; after that the job says so and stitching still checks the seams).
// run_jobs() runs many jobs on oneTBB with a bounded number in flight; the results do not
// depend on the number of threads.
#include "core/input_cleaning.hpp"
#include "core/snap.hpp"
#include "tiling/plan.hpp"
#include "tiling/tile_input.hpp"

#include <functional>
#include <vector>

namespace trisnap::tiling {

struct TileJob {
    std::size_t group = 0;
    Box core;    ///< finite box of the tile's core(s) (clipped to the data extent)
    Region report_region; ///< the core as the engine sees it (infinite outer sides)
    double halo = 0;
};

struct TileOutcome {
    std::size_t group = 0;
    double halo = 0;          ///< halo finally used
    int growths = 0;          ///< times the halo doubled
    bool cascade_unbounded = false; ///< still reaching the core at the last growth
    double cascade_x = 0, cascade_y = 0; ///< where a cascade reached the core (first growth)
    std::int64_t cascade_feature = 0;
    std::size_t input_vertices = 0;
    std::vector<std::size_t> source; ///< cleaned feature index per output
    std::vector<bool> intact;
    SnapResult result;
    double seconds = 0;
};

struct JobContext {
    const std::vector<detail::CleanFeature>& clean;
    const std::vector<bool>& has_z;
    const std::vector<Box>& boxes; ///< per cleaned feature
    const SnapOptions& options;
    int max_growth = 0; ///< 0: no cascade test (the seam check alone)
};

TileOutcome run_job(const JobContext& ctx, const TileJob& job);

/// Runs `jobs` on `threads` threads (0 = all), at most 2 x threads in flight; results in job
/// order. `done` is called (serially, in order) after each job.
std::vector<TileOutcome> run_jobs(const JobContext& ctx, const std::vector<TileJob>& jobs, int threads,
                                  const std::function<void(const TileOutcome&)>& done = {});

} // namespace trisnap::tiling
