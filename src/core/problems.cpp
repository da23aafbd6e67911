#include "core/problems.hpp"

#include <algorithm>
#include <array>

namespace trisnap {
namespace {
constexpr std::array k_catalogue{
    ProblemInfo{ProblemCode::unclosed_ring, "unclosed_ring", "ring whose last point differs from its first; it was closed"},
    ProblemInfo{ProblemCode::repeated_points, "repeated_points", "consecutive duplicate points were removed"},
    ProblemInfo{ProblemCode::degenerate_ring, "degenerate_ring", "ring with fewer than 3 distinct points was dropped"},
    ProblemInfo{ProblemCode::degenerate_line, "degenerate_line", "line with fewer than 2 distinct points was dropped"},
    ProblemInfo{ProblemCode::self_intersection, "self_intersection", "rings cross or overlap; repaired with the odd-even rule"},
    ProblemInfo{ProblemCode::non_finite_coordinate, "non_finite_coordinate", "NaN or infinite coordinate; feature rejected"},
    ProblemInfo{ProblemCode::empty_geometry, "empty_geometry", "null or empty geometry; nothing to snap"},
    ProblemInfo{ProblemCode::unsupported_geometry, "unsupported_geometry", "geometry type that is not snapped (e.g. a collection); passed through or rejected"},
    ProblemInfo{ProblemCode::huge_coordinate, "huge_coordinate", "coordinate too large for the tolerance at double precision; feature rejected"},
    ProblemInfo{ProblemCode::unreadable_geometry, "unreadable_geometry", "the driver could not read the geometry (GDAL's message says why); feature rejected"},
    ProblemInfo{ProblemCode::non_finite_z, "non_finite_z", "NaN or infinite Z; those vertices lose their Z (written as 0 unless merged with a vertex that has one)"},
    ProblemInfo{ProblemCode::collapsed_polygon, "collapsed_polygon", "polygon thinner than the tolerance vanished entirely"},
    ProblemInfo{ProblemCode::collapsed_line, "collapsed_line", "line shorter than the tolerance vanished entirely"},
    ProblemInfo{ProblemCode::part_removed, "part_removed", "some polygon or line parts vanished, others remain"},
    ProblemInfo{ProblemCode::hole_removed, "hole_removed", "a hole thinner than the tolerance closed"},
    ProblemInfo{ProblemCode::not_converged, "not_converged", "operation cap reached before the fix-point; separation may not hold here, and two features both flagged may overlap"},
    ProblemInfo{ProblemCode::drift_exceeded, "drift_exceeded", "a vertex moved further than max_drift_factor x tolerance"},
    ProblemInfo{ProblemCode::separation_not_reached, "separation_not_reached", "the requested edge separation does not hold at this place"},
    ProblemInfo{ProblemCode::topology_changed, "topology_changed", "a neck thinner than the tolerance collapsed: the feature split into more parts or holes"},
    ProblemInfo{ProblemCode::thin_part_collapsed, "thin_part_collapsed", "a spike or corridor thinner than the tolerance collapsed to a line and left the polygon"},
    ProblemInfo{ProblemCode::shared_boundary_lost, "shared_boundary_lost", "the boundary it shared with another polygon (named in the message) collapsed: both remain, but they no longer share a boundary"},
    ProblemInfo{ProblemCode::seam_mismatch, "seam_mismatch", "tiles disagreed on a seam vertex; reconciled"},
    ProblemInfo{ProblemCode::seam_cascade, "seam_cascade", "a snap cascade reached a tile halo; the tile was re-run wider"},
    ProblemInfo{ProblemCode::tile_failed, "tile_failed", "its tile failed, alone and merged with its neighbours (--on-error skip); not written"},
    ProblemInfo{ProblemCode::unreadable_feature, "unreadable_feature", "the driver could not read this feature"},
    ProblemInfo{ProblemCode::unwritable_feature, "unwritable_feature", "the driver refused to write this feature"},
    ProblemInfo{ProblemCode::value_changed, "value_changed", "the output format cannot hold a field value as it was: cut, rounded or converted (the message names the field)"},
    ProblemInfo{ProblemCode::field_renamed, "field_renamed", "the output driver renamed a field (e.g. Shapefile names of more than 10 characters); FID -1: the whole layer"},
};
} // namespace

std::span<const ProblemInfo> problem_catalogue() { return k_catalogue; }

const char* problem_name(ProblemCode code)
{
    auto it = std::find_if(k_catalogue.begin(), k_catalogue.end(),
                           [code](const ProblemInfo& p) { return p.code == code; });
    return it == k_catalogue.end() ? "unknown" : it->name;
}

} // namespace trisnap
