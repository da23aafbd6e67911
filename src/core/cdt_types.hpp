#pragma once
// The CGAL types of the engine, in one place.
//
// A plain constrained Delaunay triangulation over doubles with filtered exact predicates (Epick):
// no Constrained_triangulation_plus_2 hierarchy and no exact constructions. CGAL only records
// that an edge is constrained; who owns it (which input edges run along it) the engine keeps in
// its own flat table (core/edge_owners.hpp), and every point the engine inserts it constructs
// itself, exactly and rounded once (core/exact.hpp). The triangulation is told that constraints
// never cross (No_constraint_intersection_requiring_constructions_tag): the engine inserts a
// constraint only after its own walk found no crossing, so CGAL never falls back to its
// double-precision intersection, which can attach a crossing to the wrong endpoint (measured:
// a vertex 18 m off on Monaco with Epick + Exact_predicates_tag). Should a crossing slip
// through, CGAL throws instead of guessing.
//
// Measured before the switch (Monaco): the _plus hierarchy (a std::map of point pairs compared
// by exact coordinates) was 32-41 % of the triangulation phase, and the plain Epick CDT of the
// same constraints took 2.9-4.3x less time and 146-177 instead of 807-884 bytes per vertex.
//
// The CMake option TRISNAP_PLAIN_CT builds the engine on CGAL's Constrained_triangulation_2
// instead (no Delaunay flips), for the comparison in bench/ct-vs-cdt; the default stays the
// Delaunay one: the plain triangulation was 0-11 % slower, held the same memory and flagged more
// features (bench/results/REPORT.md, "Constrained Delaunay or not").
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "core/tracked_face.hpp"

#include <cstdint>
#include <limits>

namespace trisnap::cdt {

inline constexpr std::uint32_t k_no_id = std::numeric_limits<std::uint32_t>::max();

/// Our id of a triangulation vertex (k_no_id: not registered yet), and `seen`, the vertex's
/// place in the current search's list of seen vertices if it is there (Mesh::seen_d2: a stale
/// place names another vertex or lies past the list's end). It sits in what was the vertex's
/// padding: a vertex is 32 bytes with it or without (a point, a face handle and these two).
struct VertexInfo {
    std::uint32_t id = k_no_id;
    std::uint32_t seen = 0;
};

/// Marks stay below this: FaceInfo keeps one in 28 bits (Mesh::next_stamp wraps there).
inline constexpr std::uint32_t k_stamp_limit = std::uint32_t{1} << 28;
/// A face not labelled yet (labelling keeps the labels below it).
inline constexpr std::uint32_t k_no_label = k_stamp_limit - 1;

/// Four bytes of scratch per face. `mark` is a search's stamp (a face visited in the current
/// search, without a hash set) and, while labelling runs, the face's label (labelling sets every
/// mark back to 0 when done: the two are never needed at once). `checked` says the snapper has
/// looked at the face as it is now (core/tracked_face.hpp clears it on every change).
/// `constrained` holds CGAL's three constrained-edge flags (bit i: edge i; TrackedFace keeps them).
/// A face is then 56 bytes: three vertex and three neighbour handles, CGAL's byte of TDS data,
/// and this. With a 32-bit label beside the stamp and CGAL's `bool C[3]` it was 64 (26 MB of
/// Andorra x43's 3.2 M faces), and with a bool beside the stamp 72.
struct FaceInfo {
    std::uint32_t mark : 28 = 0;
    std::uint32_t checked : 1 = 0;
    std::uint32_t constrained : 3 = 0;
};
static_assert(sizeof(FaceInfo) == 4);

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;
using Segment = Kernel::Segment_2;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>;
using Fb = TrackedFace<Kernel, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Itag = CGAL::No_constraint_intersection_requiring_constructions_tag;
/// CtBase: the plain constrained triangulation whose edits make no Delaunay flips (the
/// triangulation itself, or its base class): core/mesh_hubs.cpp bounds CGAL's flips through it.
#ifdef TRISNAP_PLAIN_CT
using Triangulation = CGAL::Constrained_triangulation_2<Kernel, Tds, Itag>;
using CtBase = Triangulation;
inline constexpr bool k_delaunay = false;
#else
using Triangulation = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, Itag>;
using CtBase = Triangulation::Ctr;
inline constexpr bool k_delaunay = true;
#endif
using Vertex_handle = Triangulation::Vertex_handle;
using Face_handle = Triangulation::Face_handle;
static_assert(sizeof(Triangulation::Face) <= 56, "one face per triangle, twice the vertices: keep it small");
static_assert(sizeof(Triangulation::Vertex) <= 32, "one vertex per point: VertexInfo lives in its padding");

} // namespace trisnap::cdt
