#pragma once
// The engine's entry point: snap rounding of one set of features inside a constrained Delaunay
// triangulation. See snap.cpp for the method and its guarantees.
#include "core/geometry.hpp"
#include "core/problems.hpp"

#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace trisnap {

/// A half-open box [xmin, xmax) x [ymin, ymax); the default holds every point.
struct Region {
    double xmin = -std::numeric_limits<double>::infinity();
    double ymin = -std::numeric_limits<double>::infinity();
    double xmax = std::numeric_limits<double>::infinity();
    double ymax = std::numeric_limits<double>::infinity();
    bool contains(double x, double y) const { return xmin <= x && x < xmax && ymin <= y && y < ymax; }
    bool unbounded() const { return *this == Region{}; }
    /// The closed box: a point on its border counts.
    bool contains_closed(double x, double y) const { return xmin <= x && x <= xmax && ymin <= y && y <= ymax; }
    friend bool operator==(const Region&, const Region&) = default;
};

/// The tolerances the engine accepts: 2^-480 (~3.2e-145) to 2^480 (~3.1e144). Every distance
/// the engine, the tiles and the stitcher derive from t (t*t, halos of up to 32*2^10 t, frames
/// of 4 x reach, squared distances compared with t*t) must stay a finite, normal double: at
/// t = 1e308 sums overflowed to infinity (a segmentation fault), at t = 1e-202 t*t underflowed
/// to 0 and every polygon looked "thinner than the tolerance". The bounds leave 2^500 of
/// headroom on both sides, far beyond any GIS layer (coordinates stop at 2^500, see
/// k_max_coordinate).
inline constexpr double k_min_tolerance = 0x1p-480;
inline constexpr double k_max_tolerance = 0x1p+480;

/// Coordinates beyond +-2^500 (~3.3e150) are problem 109 (huge coordinate) at any tolerance:
/// squared differences of coordinates must not overflow (2^1002 < 2^1024).
inline constexpr double k_max_coordinate = 0x1p+500;

/// Progress of one engine run, and the way to stop it: called on the engine's thread with the
/// work done so far and the work in all, both measured in input vertices (after cleaning): the
/// triangulation, the snapping, the labelling and the extraction each take their share of them
/// (core/work_meter.hpp says how). `done` never decreases and the last call has done == total.
/// Calls come each time the count has grown by 1/256 of the run (at least 4096 vertices), at the
/// end of each step, and every 16,384 snapping events even when the count has not grown (a long
/// cascade), so a caller can redraw a bar and check for Ctrl-C. To cancel,
/// throw: the exception leaves snap() as it was thrown, with everything the engine held freed.
using SnapProgress = std::function<void(std::size_t done, std::size_t total)>;

/// What the engine does; every field says what changes when you flip it.
struct SnapOptions {
    /// t, in layer units: output vertices end up >= t apart. Must be in [k_min_tolerance,
    /// k_max_tolerance].
    double tolerance = 0.0;
    /// Vertex-edge promise as a factor of t: every vertex ends up >= edge_separation*t from every
    /// edge it is not an endpoint of. 0.5 is the snap-rounding guarantee (ISR, S2Builder); larger
    /// values (up to 1.0) separate more and move more.
    double edge_separation = 0.5;
    /// Case 3 (slivers): the apex of a triangle on a constrained base snaps onto the base when its
    /// distance is <= sliver_factor*t. 0 turns case 3 off (case 4 still guarantees the promise).
    /// 1.0 is the seed method's literal rule; 0.5 is the default because cascades of sliver snaps
    /// drag edges: measured max drift 3.8t -> 1.5t on dense synthetic tangles, 1.84t -> 1.14t on
    /// Monaco at 1e-5 deg, 1.73t -> 1.27t on the BGT partition at 1 m, with fewer collapses and
    /// the same separation promise.
    double sliver_factor = 0.5;
    /// Output grid step g (0 = none). Vertices are rounded to multiples of g after the fix-point;
    /// the engine snaps with margins so that the contract still holds after rounding (g <= t/4).
    double grid = 0.0;
    /// Vertices that move further than this factor of t from where they came from are reported
    /// (problem 206). The move is kept: the alternative would break separation.
    double max_drift_factor = 2.0;
    /// Cap on snapping operations; 0 picks 20 x input vertices + 1000. Reaching it is reported.
    std::size_t max_operations = 0;
    /// Where evidence is reported: a crossing (105), a collapsed edge piece (209), an unsettled
    /// vertex (205/207) and a vertex move or edge deviation (max_displacement, 206) count only
    /// when they lie in this box. The default counts everything. Tiles set it to their core, so
    /// each piece of evidence is reported by exactly one tile; snapping itself is not affected.
    Region report_region;
    /// Tiles of several plan leaves: the leaves' cores, disjoint half-open boxes whose union is
    /// the tile's core (report_region is only their bounding box, which can reach into another
    /// tile's core). The shared-boundary evidence (210) adds lengths over them, so that no piece
    /// is counted by two tiles. Empty: report_region alone.
    std::vector<Region> report_cores;
    /// Tiles: the closed box that holds every real input vertex of the layer. Edges outside it
    /// are a tile's detours round its box, not data: the shared-boundary evidence (210) ignores
    /// them. The default holds everything.
    Region data_extent;
    /// Tests: after the run, scan everything once more and count snapping events that would
    /// still apply (stats.fixpoint_misses; 0 when the engine's local re-discovery is complete).
    /// Costs one more full scan; off in normal runs.
    bool verify_fixpoint = false;
    /// Progress and cancel callback (see SnapProgress); empty: none. Does not change the result.
    SnapProgress progress;
};

/// Counters and timings of one engine run; merge runs (tiles) with +=.
struct SnapStats {
    std::size_t input_features = 0;
    std::size_t input_vertices = 0;
    std::size_t triangulation_vertices = 0; ///< after inserting constraints (incl. intersections)
    std::size_t output_vertices = 0;
    std::size_t intersections = 0;          ///< vertices created where input edges cross
    std::size_t merges = 0;                 ///< cases 1 and 2
    std::size_t splits = 0;                 ///< cases 3 and 4
    std::size_t rounds = 0;                 ///< passes over the event queue (1 + re-checks of blocked merges)
    std::size_t faces_visited = 0;          ///< faces the snapper's searches walked or re-examined (its work)
    std::size_t fixpoint_misses = 0;        ///< with verify_fixpoint: events still applicable at the end
    std::size_t collapsed_features = 0;
    double max_displacement = 0.0;          ///< largest vertex move, layer units
    double seconds_triangulate = 0.0;
    double seconds_snap = 0.0;
    double seconds_label = 0.0;
    double seconds_extract = 0.0;
    SnapStats& operator+=(const SnapStats& other);
};

/// What one run saw of a boundary two polygon features share, as evidence for problem 210
/// (shared_boundary_lost); each of the two features holds one, naming the other. A tiled run
/// merges the tiles' records of a pair (detail::merge_shared_boundaries) before judging them.
struct SharedBoundary {
    std::int64_t other = 0;          ///< the other feature's id
    std::uint64_t other_position = 0; ///< the other's position in snap()'s input (the stitch: its rank)
    bool before = false;             ///< some input edge piece of both bounds both, meeting report_region
    bool after = false;              ///< some output edge bounds both, its midpoint in report_region
    double x = 0.0;                  ///< when `before`: the smallest (x, then y) point of those pieces
    double y = 0.0;
    double length = 0.0;             ///< the length of those pieces inside report_region
    friend bool operator==(const SharedBoundary&, const SharedBoundary&) = default;
};

struct FeatureOutput {
    std::int64_t id = 0;
    Geometry geometry;              ///< Empty when the feature collapsed (then it has a problem)
    /// Largest move of any of its input vertices, or distance of a vertex now on one of its
    /// edges from that input edge: an upper bound of the output -> input drift along kept edges.
    double max_displacement = 0.0;
    /// Polygons: the other polygons it shares (or shared) a boundary with, by id (problem 210's
    /// evidence, filled when report_region, report_cores or data_extent is set, as tiles do;
    /// left at their defaults, snap() reports 210 itself and leaves this empty).
    std::vector<SharedBoundary> shared;
};

struct SnapResult {
    std::vector<FeatureOutput> features; ///< one per input feature, in input order
    std::vector<Problem> problems;       ///< sorted by feature id, then code
    SnapStats stats;
};

/// "" when t is within [k_min_tolerance, k_max_tolerance], else a one-line reason (a NaN
/// is out of range too). Inline: the config checks it without linking the engine.
inline std::string tolerance_range_error(double t)
{
    if (t >= k_min_tolerance && t <= k_max_tolerance) {
        return {};
    }
    char text[160];
    std::snprintf(text, sizeof text,
                  "tolerance %g is out of range [%g, %g]: its square and multiples would %s double precision", t,
                  k_min_tolerance, k_max_tolerance, t > 1 ? "overflow" : "underflow");
    return text;
}

/// Checks options; returns an empty string when they are usable, else a one-line reason
/// naming the option (e.g. "tolerance must be finite and > 0, got -1").
std::string validate(const SnapOptions& options);

/// Snaps `features` at `options.tolerance`. Throws std::invalid_argument when validate() fails;
/// never throws for bad geometry (that is reported as problems).
SnapResult snap(const std::vector<Feature>& features, const SnapOptions& options);
/// The same, releasing `features` as soon as the engine has its cleaned copy of them (one copy
/// of the input fewer at the engine's peak).
SnapResult snap(std::vector<Feature>&& features, const SnapOptions& options);

} // namespace trisnap
