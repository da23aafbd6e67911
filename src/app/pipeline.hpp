#pragma once
// Executes a Plan: read the layer, snap it in one engine call, write the result in input order.
// Accounting invariant: input == written + rejected + dropped + unwritable; every feature
// not written has at least one problem carrying its input FID.
#include "app/plan.hpp"
#include "app/progress.hpp"
#include "core/problems.hpp"
#include "core/snap.hpp"
#include "stitch/tiled_snap.hpp"

#include <vector>

namespace trisnap {

struct RunResult {
    std::vector<Problem> problems; ///< feature_id is the input FID; sorted by FID, then code
    std::size_t input = 0;
    std::size_t written = 0;
    std::size_t rejected = 0;      ///< not given to the engine (NaN/inf coordinates)
    std::size_t dropped = 0;       ///< the engine returned nothing (collapsed, huge coordinates, ...)
    std::size_t unwritable = 0;    ///< the driver refused them
    std::size_t snapped = 0;       ///< given to the engine
    std::size_t input_vertices = 0;
    bool fids_renumbered = false;  ///< input FIDs were missing or duplicated
    SnapStats stats;
    bool tiled = false;
    std::vector<stitch::TileReport> tiles; ///< executed tiles, by first plan leaf
    stitch::StitchStats stitch;
    double seconds_read = 0.0;
    double seconds_snap = 0.0;
    double seconds_write = 0.0;
};

/// Runs the plan. Throws io_error for I/O failures and an empty selection.
RunResult run_pipeline(Plan& plan, Progress& progress);

} // namespace trisnap
