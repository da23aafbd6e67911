#pragma once
// The numbered catalogue of geometry problems. Problems are data, not exceptions: the engine
// reports them and carries on. 1xx input repaired or rejected, 2xx snapping, 3xx seams, 9xx I/O.
#include <cstdint>
#include <span>
#include <string>

namespace trisnap {

enum class ProblemCode : int {
    // 1xx: input repaired or rejected
    unclosed_ring = 101,          ///< ring whose last point differs from its first; closed
    repeated_points = 102,        ///< consecutive duplicate points removed
    degenerate_ring = 103,        ///< ring with fewer than 3 distinct points; dropped
    degenerate_line = 104,        ///< line with fewer than 2 distinct points; dropped
    self_intersection = 105,      ///< rings cross or overlap; repaired with the odd-even rule
    non_finite_coordinate = 106,  ///< NaN or infinite coordinate; feature rejected
    empty_geometry = 107,         ///< null or empty geometry; nothing to snap
    unsupported_geometry = 108,   ///< geometry type the engine does not snap (e.g. a collection)
    huge_coordinate = 109,        ///< |coordinate| too large for the tolerance; feature rejected
    unreadable_geometry = 110,    ///< the driver failed to read the geometry; feature rejected
    non_finite_z = 111,           ///< NaN or infinite Z; those vertices lose their Z
    // 2xx: snapping
    collapsed_polygon = 201,      ///< polygon thinner than the tolerance vanished entirely
    collapsed_line = 202,         ///< line shorter than the tolerance vanished entirely
    part_removed = 203,           ///< some polygon parts or line parts vanished, others remain
    hole_removed = 204,           ///< a hole thinner than the tolerance closed
    not_converged = 205,          ///< operation cap reached before the fix-point
    drift_exceeded = 206,         ///< a vertex moved further than max_drift_factor x t
    separation_not_reached = 207, ///< the requested edge_separation factor does not hold here
    topology_changed = 208,       ///< parts or holes merged or split by snapping
    thin_part_collapsed = 209,    ///< a spike or corridor thinner than t collapsed to a line
    shared_boundary_lost = 210,   ///< a boundary shared with another polygon collapsed to points
    // 3xx: seams between tiles
    seam_mismatch = 301,          ///< tiles disagreed on a seam vertex; reconciled
    seam_cascade = 302,           ///< a snap cascade reached a tile halo; tile re-run wider
    tile_failed = 303,            ///< its tile failed twice (--on-error skip); not written
    // 9xx: I/O
    unreadable_feature = 901,     ///< the driver could not read this feature
    unwritable_feature = 902,     ///< the driver refused to write this feature
    value_changed = 903,          ///< the output cannot hold a field value as it was (cut, rounded...)
    field_renamed = 904,          ///< the output driver renamed a field (feature id -1: the layer)
};

struct ProblemInfo {
    ProblemCode code;
    const char* name;        ///< stable snake_case name used in reports
    const char* description; ///< one sentence for `trisnap problems`
};

/// Every code with its name and description, in numeric order.
std::span<const ProblemInfo> problem_catalogue();
/// The stable name of a code ("collapsed_polygon"); "unknown" for a value not in the catalogue.
const char* problem_name(ProblemCode code);

struct Problem {
    std::int64_t feature_id = 0;
    ProblemCode code = ProblemCode::empty_geometry;
    std::string message; ///< what happened, for a person
    double x = 0.0;      ///< where (layer units); NaN when there is no meaningful place
    double y = 0.0;
    /// Which input layer feature_id belongs to, when one run snaps several layers together
    /// (its index in the run's --layer list); 0 otherwise. The app sets it, never the engine,
    /// and work files do not store it (a layer's problems are tagged where they are read back).
    /// Last, so that the initialisers {id, code, message, x, y} stay valid.
    std::uint32_t layer = 0;
};

} // namespace trisnap
