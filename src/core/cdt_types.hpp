#pragma once
// The CGAL types of the engine, in one place.
//
// Kernel choice: Epeck (exact constructions) with Exact_intersections_tag. Input edges cross and
// overlap (OSM layers overlap freely); the crossing points must lie exactly on both edges, or the
// sub-edges of one constraint no longer follow it. Measured on Monaco: Epick with
// Exact_predicates_tag in Constrained_triangulation_plus_2 attached a vertex 18 m away to a ring
// (is_valid() true, no assertion), Epick with Exact_intersections_tag does not compile, Epeck with
// Exact_intersections_tag is correct at about 1.5x the build time. Every point the snapper itself
// creates is built from doubles, so lazy-exact DAGs only grow at genuine input crossings.
//
// Constrained_triangulation_plus_2 keeps, for each sub-edge, the list of input constraints that
// pass through it (its "contexts"); we insert one constraint per input edge and keep the owner of
// each constraint (feature, ring, segment) in a side table keyed by Constraint_id.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdint>
#include <limits>

namespace trisnap::cdt {

inline constexpr std::uint32_t k_no_id = std::numeric_limits<std::uint32_t>::max();

/// Our id of a triangulation vertex. CGAL creates vertices at constraint crossings and leaves
/// their info default-constructed, so k_no_id marks "not registered yet".
struct VertexInfo {
    std::uint32_t id = k_no_id;
};

/// Scratch fields for searches and labelling: `stamp` marks a face visited in the current
/// search without a hash set; `label` indexes the label table.
struct FaceInfo {
    std::uint32_t stamp = 0;
    std::uint32_t label = k_no_id;
    std::uint32_t scratch = 0; ///< per-feature index during extraction
};

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_2;
using Segment = Kernel::Segment_2;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_intersections_tag>;
using Triangulation = CGAL::Constrained_triangulation_plus_2<Cdt>;
using Vertex_handle = Triangulation::Vertex_handle;
using Face_handle = Triangulation::Face_handle;
using Constraint_id = Triangulation::Constraint_id;

struct ConstraintIdHash {
    std::size_t operator()(const Constraint_id& c) const noexcept
    {
        return std::hash<const void*>{}(c.vl_ptr());
    }
};

} // namespace trisnap::cdt
