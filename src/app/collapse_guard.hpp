#pragma once
// The collapse guard: a run that would drop much of a layer stops before it writes anything.
// Snapping drops a feature that collapses (one narrower than the tolerance); a tolerance in the
// wrong unit (metres typed as degrees on a geographic layer) drops nearly all of them, and such a
// run used to write an empty layer and exit 0. Unless [run] allow_collapse (--allow-collapse,
// --force) is set, a run stops with argument_error (exit 2) when it would drop more than 10 % of
// its features, or any feature when the tolerance is in degrees at or above the warning threshold
// (io/tolerance.hpp), and the message says which tolerance was probably meant.
// Two checks, one rule:
//  - before any snapping, the pre-check: a feature whose every two vertices are closer than the
//    tolerance collapses whatever snapping does. `snap` (and `plan`) count them in the read
//    phase and `validate` in the same read of the input (app/phases.hpp, check_read), so a
//    tolerance in the wrong unit stops in the time of one read, not after the whole snap;
//  - after snapping, for what the envelopes cannot predict (slivers, necks): `snap` and
//    `stitch` count the features that vanished at the end of the write phase, before OUT is
//    committed (its temporary is discarded, an updated GeoPackage's transaction rolled back);
//    a streamed OUT (stdout) cannot be taken back, so there the stitched features are counted
//    in one extra pass before the write phase.
#include "app/plan.hpp"
#include "app/run_phases.hpp"

#include <cstddef>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace trisnap {

/// What snapping would drop, by cause. Only collapses (201, 202: a feature narrower than the
/// tolerance) say anything about the tolerance's unit or size; features the engine rejected
/// (109: a coordinate too large for the tolerance at double precision) are named apart and
/// count only towards the share of the layer lost. Failed tiles (303) are not counted at all.
struct Drops {
    std::size_t collapsed = 0;
    std::size_t rejected = 0;
};

/// Throws argument_error when `drops` of `features` are more than the guard allows (and the
/// plan does not allow collapse): more than a tenth of the layer (collapsed and rejected
/// together), or any collapse at a tolerance in degrees above the warning threshold.
/// `predicted`: the count is validate's lower bound of collapses, not a run's.
void check_collapse(const Plan& plan, const Drops& drops, std::size_t features, bool predicted = false);

/// The stitched features that came out empty, by cause: one pass over the tiles' results
/// (after stitch); `result` holds the read phase's problems and per-layer counts.
Drops count_vanished(stitch::TiledRun& run, const RunResult& result);

/// True for a problem that says the engine rejected the feature (109) rather than snapped it away.
bool rejected_by_engine(const Problem& problem);

/// The features the engine's input cleaning rejected (109), as (input layer, FID), from the read
/// phase's problems: they reach the write phase as features without an output or a problem of
/// their own.
std::set<std::pair<std::uint32_t, std::int64_t>> rejected_features(const ProblemLog& problems);

/// Between the stitch and the write phase, for a streamed OUT only: unless the plan allows
/// collapse, counts the features the write would drop and checks them (check_collapse).
void guard_collapse(const Plan& plan, RunPhases& phases);

/// True when the diagonal of `g`'s envelope is shorter than `tolerance`: every two of its
/// vertices are closer than that, so snapping collapses it (the pre-check counts these).
bool smaller_than_tolerance(const Geometry& g, double tolerance);

} // namespace trisnap
