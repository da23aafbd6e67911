#pragma once
// Tiled runs checked like the engine's: the independent contract checker on the stitched
// output, and the comparison with an untiled run feature by feature.
#include "snap_harness.hpp"
#include "stitch/tiled_snap.hpp"

#include <string>
#include <vector>

namespace trisnap {

struct TiledRun {
    stitch::TiledResult tiled;
    ContractReport report;
};

/// Snaps tiled and checks the stitched layer, with at most `max_flagged` features exempt from
/// the drift and shared-boundary checks.
inline TiledRun tiled_and_check(const std::vector<Feature>& input, const SnapOptions& options,
                                const stitch::TilingOptions& tiling, std::size_t max_flagged)
{
    TiledRun run;
    run.tiled = stitch::snap_tiled(input, options, tiling);
    run.report = check_contract(checked_features(input), checked_features(run.tiled.result),
                                reported_problems(run.tiled.result), options.tolerance,
                                engine_rules(options, max_flagged));
    return run;
}

inline stitch::TilingOptions tiles_of(double size, int threads = 2)
{
    stitch::TilingOptions t;
    t.plan.tile_size = size;
    t.threads = threads;
    return t;
}

/// Ids of features whose output differs (full-precision WKT) between two runs.
inline std::vector<std::int64_t> differing(const SnapResult& a, const SnapResult& b)
{
    std::vector<std::int64_t> ids;
    const auto wa = output_by_id(a), wb = output_by_id(b);
    for (const auto& [id, w] : wa) {
        auto it = wb.find(id);
        if (it == wb.end() || it->second != w) ids.push_back(id);
    }
    for (const auto& [id, w] : wb)
        if (!wa.count(id)) ids.push_back(id);
    return ids;
}

/// Problems without the 3xx seam notes (which only a tiled run has).
inline std::string problems_without_seams(const std::vector<Problem>& problems)
{
    std::vector<Problem> kept;
    for (const Problem& p : problems)
        if (static_cast<int>(p.code) / 100 != 3) kept.push_back(p);
    return problem_lines(kept);
}

} // namespace trisnap
