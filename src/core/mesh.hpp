#pragma once
// The triangulation of one snapping job and the bookkeeping CGAL does not keep for us: our
// vertex ids (stable, never reused, ordered by coordinates at build time so nothing depends on
// input order or addresses), the input positions each vertex stands for, and the owner of every
// constraint. All snapping edits go through replace(), which is the one place that removes and
// re-inserts constraints (CGAL has no "move a constrained vertex").
#include "core/cdt_types.hpp"
#include "core/input_cleaning.hpp"

#include <span>
#include <unordered_map>
#include <vector>

namespace trisnap::detail {

/// Who an input edge belongs to. `part` is the ring index (polygons) or line index (lines) in
/// the CleanFeature; `seg` the edge's index along it.
struct Owner {
    std::uint32_t feature = 0;
    std::uint32_t part = 0;
    std::uint32_t seg = 0;
    bool line = false;
};

struct VertexRecord {
    cdt::Vertex_handle handle;
    double x = 0, y = 0, z = 0;
    double weight = 1;                         ///< how many vertices were merged into this one
    bool alive = true;
    std::vector<std::uint32_t> snapped_into;   ///< owners of edges this vertex was split into, once per split
};

struct EdgeHit {
    double d;
    std::uint32_t b, c; ///< b < c
};

/// One (sub-edge, owner) pair; key = (min vertex id << 32) | max vertex id.
struct SubEdgeOwner {
    std::uint64_t key;
    std::uint32_t owner;
    bool operator<(const SubEdgeOwner& o) const { return key != o.key ? key < o.key : owner < o.owner; }
};

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b)
{
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

class Mesh {
public:
    /// `reach`: the largest snapping distance; the frame corners stay further than that.
    Mesh(const std::vector<CleanFeature>& features, double reach);

    cdt::Triangulation& tri() { return m_tri; }
    const cdt::Triangulation& tri() const { return m_tri; }
    const VertexRecord& vertex(std::uint32_t id) const { return m_vertices[id]; }
    std::size_t vertex_slots() const { return m_vertices.size(); }
    std::uint32_t id(cdt::Vertex_handle h) const { return h->info().id; }
    const Owner& owner(const cdt::Constraint_id& cid) const { return m_owners[m_owner_of.at(cid)]; }
    const Owner& owner_at(std::uint32_t index) const { return m_owners[index]; }
    std::size_t intersections() const { return m_intersections; }
    static constexpr std::size_t frame_vertices = 4;
    /// A stamp no face or vertex carries yet, for marking sets of faces.
    std::uint32_t fresh_stamp() { return next_stamp(); }
    /// Vertex id of each input point, per feature, rings first then lines, in input order.
    const std::vector<std::uint32_t>& input_vertices(std::size_t feature) const { return m_input_ids[feature]; }
    /// Where an input vertex is now (follows merges).
    std::uint32_t current(std::uint32_t id);

    /// Replaces `olds` by one vertex at (x, y), re-attaching their constraints with their owners.
    /// With `split` = {b, c}, the new vertex is the exact projection of (x, y) on the constrained
    /// edge b-c and splits it. Returns the new vertex; `touched` receives the vertices whose
    /// neighbourhood changed (old and new 1-rings, crossing vertices created).
    std::uint32_t replace(std::span<const std::uint32_t> olds, double x, double y,
                          const std::uint32_t* split, std::vector<std::uint32_t>& touched);

    /// Vertices within r_vertex of vertex v and constrained edges within r_edge of it (not
    /// incident to v), whatever constraints lie between: a walk over the faces meeting the disk.
    void search_point(std::uint32_t v, double r_vertex, double r_edge,
                      std::vector<std::pair<double, std::uint32_t>>& vertices,
                      std::vector<EdgeHit>& edges);
    /// Vertices within r of the segment b-c (not b or c): a walk over faces meeting the capsule.
    void search_segment(std::uint32_t b, std::uint32_t c, double r,
                        std::vector<std::pair<double, std::uint32_t>>& vertices);
    /// Owner indices of every constraint through the sub-edge a-b (empty if not constrained).
    void owners_of_edge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const;
    bool is_constrained_edge(std::uint32_t a, std::uint32_t b) const;
    /// Every constrained sub-edge with each owner of the constraints through it, sorted by key.
    /// One sequential pass over the constraints: far cheaper than asking CGAL's hierarchy (a map
    /// keyed by exact points) edge by edge.
    std::vector<SubEdgeOwner> sub_edge_owners() const;
    /// Records that vertex v was split into edges of these owners (the guard on repeated splits).
    void note_snapped(std::uint32_t v, const std::vector<std::uint32_t>& owners);

private:
    struct Saved {
        std::vector<cdt::Vertex_handle> list;
        std::uint32_t owner;
    };
    void insert_points(const std::vector<CleanFeature>& features, double reach);
    void insert_constraints(const std::vector<CleanFeature>& features);
    void insert_edge(cdt::Vertex_handle a, cdt::Vertex_handle b, std::uint32_t owner);
    void register_created_vertices();
    std::uint32_t add_record(cdt::Vertex_handle h, double z);
    double interpolated_z(cdt::Vertex_handle h) const;
    void collect_constraints(cdt::Vertex_handle h, std::vector<Saved>& saved,
                             std::vector<std::uint32_t>& touched);
    cdt::Vertex_handle insert_target(double x, double y, const std::uint32_t* split,
                                     cdt::Face_handle hint);
    void merge_into(std::uint32_t target, std::span<const std::uint32_t> olds);
    void reinsert(const std::vector<Saved>& saved, std::vector<std::uint32_t>& touched);
    void one_ring(cdt::Vertex_handle h, std::vector<std::uint32_t>& out) const;
    std::uint32_t next_stamp();

    cdt::Triangulation m_tri;
    std::vector<VertexRecord> m_vertices;
    std::vector<std::uint32_t> m_forward;
    std::vector<Owner> m_owners;
    std::unordered_map<cdt::Constraint_id, std::uint32_t, cdt::ConstraintIdHash> m_owner_of;
    std::vector<std::vector<std::uint32_t>> m_input_ids;
    std::vector<std::uint32_t> m_vertex_stamp;
    std::uint32_t m_stamp = 0;
    std::size_t m_intersections = 0;
};

double distance_point_segment(double px, double py, double ax, double ay, double bx, double by);

} // namespace trisnap::detail
