#pragma once
// Executes a Plan as a stream of bounded phases over a work store (memory or a work directory):
//   plan   - the layer read once (geometries only: attributes are read again when writing),
//            cleaned into features.bin with a bounded sample of vertices for the tile plan;
//   spool  - the tile plan, each tile's reach box, each tile's bucket (split to the budget);
//   snap   - the tiles, in parallel, as many at once as the memory pool holds;
//   stitch - the seam check, merge-and-rerun;
//   write  - the layer read again with its attributes, in step with the stitched features,
//            written in input order.
// Every phase's files are committed in the store, so with a work directory a run that stopped
// (killed, out of memory, a node lost) continues with --resume and writes the same bytes.
// Accounting invariant: input == written + rejected + dropped + unwritable; every feature not
// written has at least one problem carrying its input FID.
#include "app/budget.hpp"
#include "app/interrupt.hpp"
#include "app/plan.hpp"
#include "app/problem_log.hpp"
#include "app/progress.hpp"
#include "app/work_dir.hpp"
#include "core/problems.hpp"
#include "io/commit_group.hpp"
#include "core/snap.hpp"
#include "stitch/tiled_snap.hpp"

#include <functional>
#include <string>
#include <vector>

namespace trisnap {

/// Time, CPU time and peak resident memory (so far) at the end of one phase.
struct PhaseRecord {
    std::string name;
    double seconds = 0;
    std::uint64_t peak_rss = 0;
    double cpu_seconds = 0; ///< of all the process's threads during the phase
};

/// One input layer's share of a run, with the same accounting:
/// input == written + rejected + dropped + unwritable.
struct LayerCounts {
    std::size_t input = 0;
    std::size_t written = 0;
    std::size_t rejected = 0;
    std::size_t dropped = 0;
    std::size_t unwritable = 0;
    std::size_t snapped = 0;
    std::size_t input_vertices = 0;
    bool fids_renumbered = false; ///< its FIDs were missing or duplicated within it: orig_fid
};

struct RunResult {
    /// feature_id is the input FID of input layer `layer`; read back sorted by layer, FID, then
    /// code (ProblemLog), held in the work store beyond a bound, so valid while the WorkDir is
    ProblemLog problems;
    std::size_t input = 0;
    std::size_t written = 0;
    std::size_t rejected = 0;      ///< not given to the engine (NaN/inf coordinates)
    std::size_t dropped = 0;       ///< the engine returned nothing (collapsed, huge coordinates, ...)
    std::size_t dropped_rejected = 0; ///< of `dropped`: the engine rejected them (109 huge coordinate)
    std::size_t unwritable = 0;    ///< the driver refused them
    std::size_t snapped = 0;       ///< given to the engine
    std::size_t input_vertices = 0;
    bool fids_renumbered = false;  ///< input FIDs were missing or duplicated (in any layer)
    std::vector<LayerCounts> layers; ///< per input layer, in --layer order (one: the totals above)
    SnapStats stats;
    bool tiled = false;
    std::vector<stitch::TileReport> tiles; ///< executed tiles, by group
    stitch::StitchStats stitch;
    double seconds_read = 0.0;
    double seconds_snap = 0.0;     ///< plan + snap + stitch
    double seconds_write = 0.0;
    std::vector<PhaseRecord> phases;
    RunBudget budget;
    std::uint64_t memory_pool = 0; ///< bytes the tiles in flight could take (0: not bounded)
    std::uint64_t spool_bytes = 0; ///< the work files at their largest
    bool resumed = false;
    double seconds_open = 0;       ///< opening the input and checking the plan
};

/// Per input layer: its FIDs are unusable in the output (WriteOptions::renumber).
std::vector<bool> renumbered_layers(const RunResult& result);

/// Runs the plan. Throws io_error for I/O failures and an empty selection, argument_error when
/// the memory limit is too small (naming the feature or tile and the smallest limit that works).
RunResult run_pipeline(Plan& plan, WorkDir& work, const RunBudget& budget, Progress& progress, InterruptGuard& interrupt);

/// Files added to OUT's commit (the report) once the run is done, before they all go into place.
using StageOutputs = std::function<void(CommitGroup&, const Plan&, const RunResult&)>;
/// What is done once OUT is in place, while the work files (the problem log) are still there.
using DeliverRun = std::function<void(const Plan&, const RunResult&)>;

/// A snap run as the CLI makes it: the budget, the work directory (continued with --resume),
/// the plan (opens the input; `plan` receives it), the pipeline, then OUT and what `stage`
/// adds renamed into place together (commit_outputs), then `deliver`; the work directory is
/// removed after that (also when `deliver` throws). `seconds_open` of the result is the plan's
/// time. The result's problem log is closed (its counts stay). `interrupt` is the command's guard.
RunResult snap_run(const SnapArgs& args, const Config& config, Progress& progress, Plan& plan, InterruptGuard& interrupt,
                   const StageOutputs& stage = {}, const DeliverRun& deliver = {});

/// The end of a run that writes files: a last check for a signal (after the report was
/// staged, and again once the targets are checked, before any is touched), the renames, and
/// from then on the run is complete (a signal no longer stops it).
void commit_outputs(CommitGroup& outputs, InterruptGuard& interrupt);

/// The manifest of a run for its work directory: what must match for --resume.
std::string run_manifest(const Plan& plan);

} // namespace trisnap
