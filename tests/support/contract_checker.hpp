#pragma once
// An independent, brute-force-in-spirit checker of the trisnap contract. It shares no code with
// the engine on purpose: features come in as WKT strings and are read by GEOS, distances and
// indexes are written here from scratch, so a bug in the engine's geometry types or predicates
// cannot hide itself. Every measurement goes through a spatial index (a uniform grid over
// segment pieces, GEOS STRtree over features), so 2*10^5 vertices take seconds, not hours.
//
// What it measures, for output `out` of snapping input `in` at tolerance t:
//  - n_missing: input ids with no (non-empty) output and no problem whose code says the feature
//    is not written (ContractRules::not_written_codes): a feature that only had, say, repeated
//    points removed (102) and vanished is missing;
//  - n_flagged: output features carrying a problem code that exempts them from the drift and
//    shared-boundary checks (ContractRules::drift_codes); more than the case allows
//    (ContractRules::max_flagged) breaks the contract, so an engine that flags everything
//    cannot pass;
//  - n_invalid: output features GEOS calls invalid (or unparsable, of another dimension than
//    their input, or with an id that is not in the input);
//  - min_vertex_vertex: smallest distance between two DISTINCT output coordinates (equal
//    coordinates are one vertex: shared boundaries and closing points are not defects);
//  - min_vertex_edge: smallest distance from an output vertex to an output segment it is not an
//    endpoint of (exact coordinate equality decides "endpoint of");
//  - max_hausdorff: largest symmetric Hausdorff distance between a feature's input and output;
//  - n_overlaps_new: output polygon pairs overlapping with area > 1e-9 t^2 whose inputs did not,
//    except pairs where both features carry a code saying the run stopped before its fix-point
//    there (ContractRules::unfinished_codes): those count in n_overlaps_new_reported;
//  - n_shared_lost: input polygon pairs sharing > t/2 of boundary whose outputs share no
//    boundary of positive length any more, or now overlap (unless both carry an unfinished code:
//    that overlap is counted once, in n_overlaps_new_reported). Pairs where either output is empty
//    (collapsed, and reported as a problem) are not counted; a lost pair the engine reported
//    (ContractRules::lost_boundary_codes) counts in n_shared_lost_reported instead.
// Distances are searched up to 2t: when no pair is closer, the minimum is reported as +infinity.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace trisnap {

struct CheckedFeature {
    std::int64_t id = 0;
    std::string wkt; ///< empty text or "... EMPTY" means the feature has no output geometry
};

/// A problem the engine reported, as the checker sees it: the feature and the code's number
/// (the checker knows no engine type on purpose).
struct ReportedProblem {
    std::int64_t id = 0;
    int code = 0;
};

/// What a test case allows. The code lists come from the caller (the engine's catalogue is not
/// the checker's business); max_flagged is stated per case.
struct ContractRules {
    /// Vertex-edge promise as a factor of t (decides n_close_vertex_edge and ok()).
    double edge_factor = 0.5;
    /// Codes meaning "this feature is not in the output": only these excuse a missing feature.
    std::vector<int> not_written_codes;
    /// Codes after which a feature may legitimately drift further than 2t and lose shared
    /// boundaries (part of it collapsed or was repaired): such features are left out of
    /// max_hausdorff and n_shared_lost (new overlaps are still counted for them).
    std::vector<int> drift_codes;
    /// At most this many output features may carry a drift code.
    std::size_t max_flagged = 0;
    /// Codes that report a lost shared boundary (and nothing else): a pair whose boundary is lost
    /// (not one that now overlaps) with such a code on either feature counts in
    /// n_shared_lost_reported instead of n_shared_lost. Each case states how many it expects.
    std::vector<int> lost_boundary_codes;
    /// Codes saying the run stopped before its fix-point where the feature is (the engine's
    /// operation cap): a new overlap between two features that BOTH carry such a code counts in
    /// n_overlaps_new_reported instead of n_overlaps_new. A run stopped between two edits can
    /// hold a fold the next edit would have closed; one of the two features alone does not excuse it.
    std::vector<int> unfinished_codes;
};

struct ContractReport {
    double tolerance = 0.0;
    std::size_t n_in = 0;
    std::size_t n_out = 0; ///< output features with a non-empty geometry
    std::size_t n_missing = 0;
    std::size_t n_flagged = 0;   ///< output features exempt from drift and shared-boundary checks
    std::size_t max_flagged = 0; ///< as the rules allowed
    std::size_t n_invalid = 0;
    std::size_t n_overlaps_new = 0;
    std::size_t n_overlaps_new_reported = 0; ///< new, between two features with an unfinished code
    std::size_t n_shared_lost = 0;
    std::size_t n_shared_lost_reported = 0; ///< lost, with a lost_boundary_codes problem on either
    std::size_t n_close_vertex_pairs = 0; ///< distinct vertex pairs closer than t
    std::size_t n_close_vertex_edge = 0;  ///< vertex-segment pairs closer than edge_factor*t
    double min_vertex_vertex = 0.0;       ///< +infinity when no pair is within 2t
    double min_vertex_edge = 0.0;         ///< +infinity when no pair is within 2t
    double max_hausdorff = 0.0;
    std::int64_t max_hausdorff_id = 0;    ///< the feature where max_hausdorff was measured
    /// One line per defect with ids and coordinates, at most a few per kind (about 20 in all).
    std::vector<std::string> examples;

    /// True when every promise holds: nothing missing or invalid, vertices >= t apart, vertices
    /// >= edge_factor*t from edges, Hausdorff <= max_drift, no new overlaps, no lost boundaries,
    /// no more flagged features than allowed.
    bool ok(double t, double edge_factor, double max_drift) const;
    /// A few lines: counts, minima in units of t, then the examples.
    std::string summary() const;
};

/// Measures the contract. Throws std::invalid_argument when an INPUT WKT does not parse or
/// tolerance is not > 0 (a bad test), while an unparsable output is counted as invalid.
ContractReport check_contract(const std::vector<CheckedFeature>& input,
                              const std::vector<CheckedFeature>& output,
                              const std::vector<ReportedProblem>& problems, double tolerance,
                              const ContractRules& rules);

/// Rules for checker self-tests on hand-made outputs: no problem excuses anything, nothing may
/// be flagged, vertex-edge factor 0.5.
ContractReport check_contract(const std::vector<CheckedFeature>& input,
                              const std::vector<CheckedFeature>& output, double tolerance);

/// GoogleTest adaptor: EXPECT_TRUE(contract_holds(report, t)) prints the summary on failure.
::testing::AssertionResult contract_holds(const ContractReport& report, double t,
                                          double edge_factor = 0.5,
                                          double max_drift_factor = 2.0);

} // namespace trisnap
