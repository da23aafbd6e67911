#pragma once
// What every engine test does: run snap(), hand input and output as WKT to the independent
// contract checker, and keep both so a test can look further. Shared by unit_core,
// golden_cases and real_data.
#include "contract_checker.hpp"
#include "problem_codes.hpp" // not_written_codes()
#include "core/geometry.hpp"
#include "core/snap.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace trisnap {

/// Problem codes after which a feature may legitimately drift further than 2t and lose shared
/// boundaries (part of it collapsed or was repaired): 105, 201-204, 206, 209.
const std::vector<int>& drift_codes();

/// The checker's rules for an engine run with `options`, allowing `max_flagged` features to
/// carry a drift code (each test case states how many it expects at most).
ContractRules engine_rules(const SnapOptions& options, std::size_t max_flagged);

/// The problems as the checker sees them (id, code number).
std::vector<ReportedProblem> reported_problems(const SnapResult& result);

struct CheckedRun {
    SnapResult result;
    ContractReport report;
    double seconds_snap = 0.0;
    double seconds_check = 0.0;
};

/// Input as the checker can read it: unclosed rings closed, rings under 4 points and lines
/// under 2 dropped, features with a non-finite coordinate emptied (GEOS rejects all of these).
std::vector<CheckedFeature> checked_features(const std::vector<Feature>& features);
std::vector<CheckedFeature> checked_features(const SnapResult& result);

/// Snaps `input` with `options` (and verify_fixpoint: expects no missed snapping event) and
/// measures the contract at options.tolerance, with the engine's edge_separation as the
/// checker's edge factor and at most `max_flagged` features exempt from the drift and
/// shared-boundary checks.
CheckedRun snap_and_check(const std::vector<Feature>& input, const SnapOptions& options,
                          std::size_t max_flagged);

/// Options with only the tolerance (and optionally the grid) set.
SnapOptions options_at(double tolerance, double grid = 0.0);

/// "id code" per problem, sorted, one per line: compact and diffable.
std::string problem_lines(const std::vector<Problem>& problems);
/// id -> full-precision WKT of every output feature, for order-independent comparisons.
std::map<std::int64_t, std::string> output_by_id(const SnapResult& result);
/// How many problems carry `code`.
std::size_t count_code(const SnapResult& result, ProblemCode code);
/// Whether feature `id` has a problem with `code`.
bool has_problem(const SnapResult& result, std::int64_t id, ProblemCode code);

/// Output features as input features (same ids, empty ones left out): to snap an output again.
std::vector<Feature> output_as_input(const SnapResult& result);

/// One line for logs: counts, minima in units of t, Hausdorff, problems and times.
std::string figures_line(const std::string& name, const CheckedRun& run, double t);

} // namespace trisnap

