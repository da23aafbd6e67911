#pragma once
// The triangulation of one snapping job and the bookkeeping CGAL does not keep for us: our
// vertex ids (stable, never reused, ordered by coordinates at build time so nothing depends on
// input order or addresses), the input positions each vertex stands for, and the owners of every
// constrained edge (core/edge_owners.hpp). Every constraint goes in through insert_segment(),
// which walks the triangulation first and splits the segment at vertices lying on it and at
// crossings (constructed exactly, rounded once: core/exact.hpp), so CGAL never meets a crossing.
// All snapping edits go through replace() (CGAL has no "move a constrained vertex").
#include "core/cdt_types.hpp"
#include "core/edge_owners.hpp"
#include "core/input_cleaning.hpp"
#include "core/long_edges.hpp"
#include "core/work_meter.hpp"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_set>
#include <utility>
#include <vector>

namespace trisnap::detail {

/// Who an input edge belongs to, and where: `at` is the place of its first end in the mesh's
/// input ids, its second end the next place (rings are kept closed there: Mesh::input_vertices).
/// Mesh::owner_from() and owner_to() give the ends' vertex ids when the triangulation was built
/// (input points, whose records keep them; follow merges with Mesh::current()). One per input
/// edge: 8 bytes (the flag in the feature's top bit: the build refuses 2^31 features or input
/// points and more, a length_error before anything is made, so places fit 32 bits). The ends'
/// ids were kept in it until 2026-12-03: 12 bytes, 7.7 MB more of Andorra x43's untiled peak.
struct Owner {
    std::uint32_t feature : 31 = 0;
    std::uint32_t line : 1 = 0;
    std::uint32_t at = 0;
};
static_assert(sizeof(Owner) <= 8, "Owner is one per input edge: keep it small");

/// A vertex's coordinates.
struct Xy {
    double x = 0, y = 0;
};

/// 16 bytes: one per triangulation vertex, the engine's largest table after CGAL's own. Where
/// the vertex's point is: while the vertex is in the triangulation, in its CGAL vertex (`at`
/// holds that vertex's address: even); once it is removed, or the triangulation is freed, in
/// Mesh::m_kept (`at` holds (place << 1) | 1). The point was kept here beside CGAL's until
/// 2026-12-03: 32 bytes a vertex, 27 MB of Andorra x43's untiled peak. The rare list of owners
/// a vertex was split into lives beside it (Mesh::snapped_into), and so do the z values
/// (Mesh::z), which a layer without them does not hold at all. A removed vertex keeps its slot
/// (`alive` false) and its point, so an input point's record is that point for good.
struct VertexSlot {
    std::uintptr_t at = 0; ///< 0 only in the build, before the vertex is in the triangulation
    /// How many input points were merged into this one (0 for a crossing until the build ends):
    /// the weight of its centroid. At most the run's input points: 31 bits hold it (2^31 points
    /// in one engine run would take ~800 GB), and it converts to a double exactly.
    std::uint32_t weight : 31 = 1;
    std::uint32_t alive : 1 = 1;
    std::uint32_t snapped = cdt::k_no_id; ///< its list in Mesh::m_snapped, if it has one
    bool in_triangulation() const { return at != 0 && (at & 1) == 0; }
};
static_assert(sizeof(VertexSlot) <= 16, "VertexSlot is one per vertex: keep it small");

/// What Mesh::vertex() reads of a vertex, by value.
struct VertexRecord {
    cdt::Vertex_handle handle; ///< null once it is out of the triangulation
    double x = 0, y = 0;
    std::uint32_t weight = 1;
    bool alive = true;
    std::uint32_t snapped = cdt::k_no_id;
};

/// How many times a polygon feature owns one edge.
struct FeatureCount {
    std::uint32_t feature;
    std::uint32_t times;
};

struct EdgeHit {
    double d2; ///< squared distance
    std::uint32_t b, c; ///< b < c
};

/// Room for n per-vertex (or per-edge) entries and the few per cent more that crossings and the
/// snapper's edits add: a table reserved exactly doubles at the first one (Andorra x43 untiled:
/// 1.6 M records, 100 MB unused; 1,763 crossings doubled the owner table's 13 MB of entries).
inline std::size_t with_room(std::size_t n)
{
    return n + n / 32 + 256;
}

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b)
{
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

class Mesh {
public:
    /// `reach`: the largest snapping distance; the frame corners stay further than that.
    /// `meter` (optional) hears the points and constraints steps.
    Mesh(const std::vector<CleanFeature>& features, double reach, WorkMeter* meter = nullptr);
    /// The same, and frees `features` as soon as the vertex records hold their points, before
    /// CGAL's vertices and faces are made, keeping only their `outlines` (counts, flags, first
    /// points): input_vertices() and vertex() give every input point from then on. The cleaned
    /// copy was 40 bytes per input vertex beside the whole build (Andorra x43 untiled: 76 MB).
    Mesh(std::vector<CleanFeature>&& features, double reach, WorkMeter* meter, Outlines& outlines);

    cdt::Triangulation& tri() { return m_tri; }
    const cdt::Triangulation& tri() const { return m_tri; }
    VertexRecord vertex(std::uint32_t id) const
    {
        const VertexSlot& s = m_vertices[id];
        VertexRecord r;
        r.handle = handle(id);
        const Xy p = xy(id);
        r.x = p.x;
        r.y = p.y;
        r.weight = s.weight;
        r.alive = s.alive;
        r.snapped = s.snapped;
        return r;
    }
    bool alive(std::uint32_t id) const { return m_vertices[id].alive; }
    /// Vertex id's coordinates (where it was made: vertices never move).
    Xy xy(std::uint32_t id) const
    {
        const std::uintptr_t at = m_vertices[id].at;
        assert(at != 0);
        if ((at & 1) == 0) {
            const cdt::Point& p = reinterpret_cast<const cdt::Triangulation::Vertex*>(at)->point();
            return {p.x(), p.y()};
        }
        return m_kept[at >> 1];
    }
    /// Vertex id's CGAL vertex; null once it is out of the triangulation.
    cdt::Vertex_handle handle(std::uint32_t id) const
    {
        const VertexSlot& s = m_vertices[id];
        return s.in_triangulation() ? cdt::Vertex_handle(reinterpret_cast<cdt::Triangulation::Vertex*>(s.at))
                                    : cdt::Vertex_handle();
    }
    /// The z of a vertex: NaN where it has none (every vertex, when no input point had one).
    double z(std::uint32_t id) const { return m_z.empty() ? std::numeric_limits<double>::quiet_NaN() : m_z[id]; }
    /// Whether the mesh holds z values (some vertex has had one).
    bool holds_z() const { return !m_z.empty(); }
    /// Whether vertex id is an input point. Vertices never move (an edit removes vertices and
    /// inserts new ones), so an input point's vertex, while alive, is exactly where it was read.
    bool is_input_point(std::uint32_t id) const { return id < m_input_points; }
    std::size_t vertex_slots() const { return m_vertices.size(); }
    /// The squared distance of two vertices as the searches compute it (search_point's
    /// distances are these, bit for bit, either way round).
    double vertex_d2(std::uint32_t a, std::uint32_t b) const { return point_d2(xy(a), xy(b)); }
    static double point_d2(const Xy& a, const Xy& b)
    {
        const double ex = b.x - a.x;
        const double ey = b.y - a.y;
        return ex * ex + ey * ey;
    }
    std::uint32_t id(cdt::Vertex_handle h) const { return h->info().id; }
    const Owner& owner_at(std::uint32_t index) const { return m_owners[index]; }
    /// The vertex ids of an input edge's ends when the triangulation was built.
    std::uint32_t owner_from(const Owner& o) const { return m_input_ids[o.at]; }
    std::uint32_t owner_to(const Owner& o) const { return m_input_ids[o.at + 1]; }
    std::size_t intersections() const { return m_intersections; }
    /// Faces the searches have walked so far (a measure of the snapper's work).
    std::size_t faces_walked() const { return m_faces_walked; }
    /// 64 ulps of the largest coordinate: far above the rounding of any distance the mesh computes.
    double ulp_margin() const { return m_ulp_margin; }
    /// The work of CGAL's hole fills so far: the sum of the squared degrees of the vertices it
    /// removed (fill_hole_delaunay makes d^2 tests), and how many removals went through rounds of
    /// flips first (core/mesh_hubs.cpp).
    std::size_t removal_work() const { return m_removal_work; }
    std::size_t hub_removals() const { return m_hub_removals; }
    /// Whether an edit left CGAL's own path (a bound was hit; core/mesh_hubs.cpp).
    bool bounds_hit() const { return m_non_delaunay; }
    /// Constrained edges at least this long (squared) are "long"; the mesh counts them as edits
    /// make and remove edges. The snapper sets the length below which no edge can give a split
    /// event; while no edge is that long, search_point's nearest-only walk need not reach the
    /// edge radius (see there), nor once the long edges are in their grid (core/long_edges.hpp).
    /// 0 (the default) counts every edge.
    void set_long_edge_length2(double len2);
    std::size_t long_edges() const { return m_long_edges; }
    /// The bounds on CGAL's edits (core/mesh_hubs.cpp): above `hub_degree` a vertex is removed by
    /// rounds of flips first (down to 64, or `hub_degree` if lower); an insertion makes at most
    /// `flip_budget` flips (<= 96, CGAL's recursion depth being 100). Defaults 1024 and 96; tests
    /// lower them to stress the paths that leave the triangulation not Delaunay; `check_each_edit` then has every insertion and
    /// removal verify the triangulation (CGAL's is_valid of the plain one, O(n): tests only) and
    /// throw std::logic_error when it is not valid.
    void set_edit_bounds(std::size_t hub_degree, int flip_budget, bool check_each_edit = false)
    {
        m_hub_degree = hub_degree;
        m_flip_budget = std::clamp(flip_budget, 0, 96);
        m_check_edits = check_each_edit;
    }
    static constexpr std::size_t frame_vertices = 4;
    /// A stamp no face or vertex carries yet, for marking sets of faces.
    std::uint32_t fresh_stamp() { return next_stamp(); }
    /// The stamps handed out so far; tests set it near cdt::k_stamp_limit to cross the wrap,
    /// where every face and vertex mark is cleared (faces keep a stamp in 28 bits).
    std::uint32_t stamps_used() const { return m_stamp; }
    void set_stamps_used(std::uint32_t n) { m_stamp = std::min(n, cdt::k_stamp_limit - 1); }
    /// Vertex id of each input point, per feature, rings first then lines, in input order; each
    /// ring closed (its first point's id again after its last), so an input edge's ends are
    /// always two places one after the other (Owner::at).
    std::span<const std::uint32_t> input_vertices(std::size_t feature) const
    {
        return {m_input_ids.data() + m_input_first[feature], m_input_first[feature + 1] - m_input_first[feature]};
    }
    /// Where an input vertex is now (follows merges).
    std::uint32_t current(std::uint32_t id);

    /// Replaces `olds` by one vertex at (x, y), re-attaching their constrained edges with their
    /// owners. With `split` = {b, c}, the new vertex is the foot of (x, y) on the constrained
    /// edge b-c (rounded) and b-c is routed through it. Returns the new vertex; last_created()
    /// and last_new_edges() then tell what else the edit made.
    std::uint32_t replace(std::span<const std::uint32_t> olds, double x, double y, const std::uint32_t* split);
    /// Crossing vertices the last replace() created.
    const std::vector<std::uint32_t>& last_created() const { return m_created; }
    /// Constrained edges the last replace() inserted (re-attached, split or rerouted pieces).
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& last_new_edges() const { return m_new_edges; }

    /// Vertices within sqrt(r2_vertex) of vertex v and constrained edges within sqrt(r2_edge)
    /// of it (not incident to v), with squared distances, whatever constraints lie between: a
    /// walk over the faces meeting the disk.
    /// `nearest_only`: the caller wants, of the vertices, only the nearest (and every vertex as
    /// near), and of the edges only those at least the long-edge length: the walk then shrinks to
    /// the nearest distance found so far plus an eighth of it (at least 64 ulps of the
    /// coordinates), never below sqrt(r2_edge) while a long edge exists; `vertices` holds the
    /// nearest ones and possibly others, `edges` every long edge within sqrt(r2_edge) and
    /// possibly others. `passed_over` (edge_key pairs with v) names vertices that do not count
    /// as the nearest: the walk shrinks to the nearest of the others, and `vertices` holds every
    /// one of those as near as it (and possibly passed-over ones).
    void search_point(std::uint32_t v, double r2_vertex, double r2_edge,
                      std::vector<std::pair<double, std::uint32_t>>& vertices,
                      std::vector<EdgeHit>& edges, bool nearest_only = false,
                      const std::unordered_set<std::uint64_t>* passed_over = nullptr);
    /// Vertices within sqrt(r2) of the segment b-c (not b or c), with squared distances: a walk
    /// over faces meeting the capsule.
    void search_segment(std::uint32_t b, std::uint32_t c, double r2,
                        std::vector<std::pair<double, std::uint32_t>>& vertices);
    /// Whether the segment a-b is free: no vertex strictly inside it and no constrained edge
    /// crossing it (edges at a or b do not count). The walk along the segment that inserting a
    /// constraint makes (first_obstacle), so its cost is the faces the segment crosses.
    bool segment_is_free(std::uint32_t a, std::uint32_t b) const
    {
        return first_obstacle(handle(a), handle(b)).kind == Obstacle::Kind::none;
    }
    /// Owner indices of the edge a-b (empty if it is not constrained).
    void owners_of_edge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const;
    /// The owners of a-b oriented from a to b (appended).
    void owner_refs(std::uint32_t a, std::uint32_t b, std::vector<OwnerRef>& out) const { m_edge_owners.get(a, b, out); }
    bool is_constrained_edge(std::uint32_t a, std::uint32_t b) const { return m_edge_owners.contains(a, b); }
    /// Whether a-b is an edge of the triangulation that CGAL holds as constrained (never when
    /// either vertex was merged away).
    bool is_triangulation_constraint(std::uint32_t a, std::uint32_t b) const
    {
        if (!m_vertices[a].alive || !m_vertices[b].alive) {
            return false;
        }
        cdt::Face_handle f;
        int i = 0;
        return m_tri.is_edge(handle(a), handle(b), f, i) && f->is_constrained(i);
    }
    /// Calls f(u, v, OwnerRef) for every owner of every constrained edge (u < v, oriented u->v).
    template <class F>
    void for_each_owned_edge(F&& f) const { m_edge_owners.for_each(f); }
    /// Calls f(u, v, std::span<const OwnerRef>) once per constrained edge with all its owners.
    template <class F>
    void for_each_edge_with_owners(F&& f) const
    {
        std::vector<OwnerRef> buffer;
        m_edge_owners.for_each_grouped(f, buffer);
    }
    /// The polygon features among `refs`, each with how many of them it is, by feature. Labels
    /// toggle a feature across an edge it owns an odd number of times; owned twice or more, its
    /// edges overlap there; an even number of times, the piece bounds nothing of it.
    void polygon_ownership(std::span<const OwnerRef> refs, std::vector<FeatureCount>& out) const;
    /// Records that vertex v was split into edges of these owners (the guard on repeated splits).
    void note_snapped(std::uint32_t v, const std::vector<std::uint32_t>& owners);
    /// The owners of edges vertex v was split into, once per split (and those of the vertices
    /// merged into it).
    const std::vector<std::uint32_t>& snapped_into(std::uint32_t v) const;
    /// Frees the searches' scratch once no more searches are coming (after the snapper); a later
    /// search would allocate it again.
    void release_search_scratch()
    {
        std::vector<Seen>().swap(m_seen);
        drop_long_index();
    }
    /// Frees the owner tables (which input edges run along which edges) once nothing reads them
    /// any more; snap.cpp takes the evidence and the lines' edges out first.
    void release_owners();
    /// Frees CGAL's triangulation and the edits' scratch once the outputs' edges are taken out of
    /// it (core/extraction.hpp), so the outputs are made in the memory it held (Andorra x43
    /// untiled: 230 MB of faces and vertices). The vertices' slots stay, every point moved to
    /// m_kept first (coordinates, z, forwarding, input ids: the outputs and the drift read
    /// them); handle() is null for every vertex from then on, and nothing that reads the
    /// triangulation or the owners may be called after it.
    void release_triangulation();
    /// Whether the long edges are in a grid (core/long_edges.hpp; for the tests).
    bool long_edges_indexed() const { return m_long_indexed; }

private:
    struct Job {
        cdt::Vertex_handle a, b;
        std::uint32_t first, count; ///< owners in m_arena, oriented a -> b
    };
    struct Obstacle {
        enum class Kind { none, vertex, crossing } kind = Kind::none;
        cdt::Vertex_handle v; ///< Kind::vertex: a vertex inside the segment
        cdt::Face_handle f;   ///< Kind::crossing: the constrained edge (f, i) crossing it
        int i = 0;
    };
    struct Saved {
        cdt::Vertex_handle other;
        std::uint32_t first, count; ///< owners in m_arena, oriented from the old vertex to `other`
    };

    // mesh_build.cpp
    /// Returns each ring's and line's point count, features in order, rings then lines, and
    /// makes `outlines` of `features`. `release`, when given, is `features`: freed once the
    /// records hold the points.
    std::vector<std::uint32_t> insert_points(const std::vector<CleanFeature>& features, double reach, WorkMeter* meter,
                                             Outlines& outlines, std::vector<CleanFeature>* release);
    void insert_constraints(const std::vector<Outline>& features, const std::vector<std::uint32_t>& path_sizes,
                            WorkMeter* meter);
    /// Gives each ring's closing place in the input ids its first point's id.
    void close_rings(const std::vector<Outline>& features, const std::vector<std::uint32_t>& path_sizes);
    void build(const std::vector<CleanFeature>& features, double reach, WorkMeter* meter, Outlines& outlines,
               std::vector<CleanFeature>* release);
    void register_created_vertices(std::size_t first_created);
    std::uint32_t add_record(cdt::Vertex_handle h, double z);
    void set_z(std::uint32_t id, double z);
    double interpolated_z(cdt::Vertex_handle h);
    // mesh_insert.cpp
    cdt::Vertex_handle insert_point(const cdt::Point& p, cdt::Face_handle hint);
    void insert_segment(cdt::Vertex_handle a, cdt::Vertex_handle b, std::span<const OwnerRef> owners);
    void run_jobs();
    Obstacle first_obstacle(cdt::Vertex_handle a, cdt::Vertex_handle b) const;
    void resolve_crossing(const Job& job, cdt::Face_handle f, int i);
    bool reroute(cdt::Vertex_handle r, cdt::Vertex_handle l, cdt::Vertex_handle via);
    void push_job(cdt::Vertex_handle a, cdt::Vertex_handle b, std::uint32_t first, std::uint32_t count);
    void constrain(const Job& job);
    // mesh_hubs.cpp
    cdt::Vertex_handle insert_bounded(const cdt::Point& p, cdt::Triangulation::Locate_type lt, cdt::Face_handle loc,
                                      int li);
    void propagate_flip(cdt::Face_handle f, int i, int& budget);
    void remove_incident_constraints_bounded(cdt::Vertex_handle h);
    void remove_bounded(cdt::Vertex_handle h);
    void shrink_hub(cdt::Vertex_handle h);
    // mesh_edit.cpp
    void collect_constraints(cdt::Vertex_handle h, std::span<const std::uint32_t> olds);
    cdt::Vertex_handle insert_target(double x, double y, const std::uint32_t* split, cdt::Face_handle hint);
    void merge_into(std::uint32_t target, std::span<const std::uint32_t> olds);
    void take_edge_z(std::uint32_t v, std::uint32_t b, std::uint32_t c);
    void one_ring(cdt::Vertex_handle h, std::vector<std::uint32_t>& out) const;
    // Every owner goes in and out through these two, so the long edges stay counted.
    void add_owner(std::uint32_t a, std::uint32_t b, OwnerRef ref)
    {
        if (m_edge_owners.add(a, b, ref)) {
            count_edge(a, b, 1);
        }
    }
    void take_owners(std::uint32_t a, std::uint32_t b, std::vector<OwnerRef>& out)
    {
        const std::size_t before = out.size();
        m_edge_owners.take(a, b, out);
        if (out.size() > before) {
            count_edge(a, b, -1);
        }
    }
    bool is_long(std::uint32_t a, std::uint32_t b) const { return vertex_d2(a, b) >= m_long2; }
    void count_edge(std::uint32_t a, std::uint32_t b, int delta)
    {
        if (is_long(a, b)) {
            m_long_edges += static_cast<std::size_t>(delta);
            if (m_long_indexed) {
                index_long_edge(a, b, delta);
            }
        }
    }
    // mesh_search.cpp: the long edges' grid, built once walks held at the edge radius grow
    // costly (see search_point), then kept up to date by count_edge().
    void add_long_edges_near(std::uint32_t v, double r2_edge, std::vector<EdgeHit>& edges) const;
    void note_floored_walk(std::size_t faces, double r2_edge);
    void build_long_index(double r2_edge);
    void index_long_edge(std::uint32_t a, std::uint32_t b, int delta);
    void drop_long_index();
    std::uint32_t next_stamp();

    cdt::Triangulation m_tri;
    std::vector<VertexSlot> m_vertices;
    /// The points of the vertices out of the triangulation (VertexSlot::at).
    std::vector<Xy> m_kept;
    /// Moves vertex id's point from its CGAL vertex to m_kept: before CGAL removes the vertex.
    void keep_point(std::uint32_t id);
    static std::uintptr_t address(cdt::Vertex_handle h) { return reinterpret_cast<std::uintptr_t>(&*h); }
    /// The vertices' z, by id; empty while every z is NaN (a 2D layer: 16 MB fewer on Andorra
    /// x43 untiled, and no interpolation for crossings). Once a z is set, as long as m_vertices.
    std::vector<double> m_z;
    std::uint32_t m_input_points = 0; ///< ids below it are the input's distinct points
    std::vector<std::vector<std::uint32_t>> m_snapped; ///< VertexSlot::snapped indexes it
    std::vector<std::uint32_t> m_forward;
    std::vector<Owner> m_owners;
    EdgeOwners m_edge_owners;
    /// input_vertices() of every feature, one after another (a vector per feature held ~7 MB more
    /// on Andorra x43); feature f's start at m_input_first[f]. At most 2^31 points and a third as
    /// many closing places: places fit 32 bits.
    std::vector<std::uint32_t> m_input_ids;
    std::vector<std::size_t> m_input_first;
    // The vertices the current search has seen, with their squared distances, in the order
    // seen; a vertex's place in it is in its VertexInfo::seen (a sparse set: a place that is past
    // the end or names another vertex is left from an earlier search). Each search starts it
    // empty, so nothing is put back, also after an exception. Until 2026-12-03 a table of 8
    // bytes a vertex (13 MB of Andorra x43's untiled peak) held the distances, and before that a
    // stamp per vertex besides.
    struct Seen {
        std::uint32_t id;
        double d2;
    };
    std::vector<Seen> m_seen;
    /// Vertex h's squared distance in the current search, NaN when it has not seen h.
    double seen_d2(cdt::Vertex_handle h) const
    {
        const std::uint32_t s = h->info().seen;
        return s < m_seen.size() && m_seen[s].id == h->info().id ? m_seen[s].d2 : std::numeric_limits<double>::quiet_NaN();
    }
    void mark_seen(cdt::Vertex_handle h, double d2)
    {
        h->info().seen = static_cast<std::uint32_t>(m_seen.size());
        m_seen.push_back(Seen{h->info().id, d2});
    }
    std::uint32_t m_stamp = 0;
    std::size_t m_intersections = 0;
    std::size_t m_faces_walked = 0;
    std::size_t m_removal_work = 0;
    double m_long2 = 0;
    std::size_t m_long_edges = 0;
    LongEdgeIndex m_long_index;
    bool m_long_indexed = false;     ///< m_long_index holds every long edge but m_long_apart
    bool m_long_index_tried = false; ///< built, or found not worth it, once this run
    std::vector<std::uint64_t> m_long_apart; ///< long edges too long for the grid (a few)
    std::size_t m_floored_walks = 0; ///< nearest-only walks held at the edge radius, before the grid
    std::size_t m_floored_faces = 0; ///< and the faces they walked
    double m_ulp_margin = 0; ///< 64 ulps of the largest coordinate (the frame's)
    bool m_non_delaunay = false; ///< a bound left an edge as it was (core/mesh_hubs.cpp)
    std::size_t m_hub_degree = 1024;
    int m_flip_budget = 96;
    bool m_check_edits = false;
    void check_edit(const char* what) const;
    std::size_t m_hub_removals = 0;
    // Scratch of insert_segment() and replace(), kept to avoid allocating per call.
    std::vector<Job> m_jobs;
    std::vector<OwnerRef> m_arena;
    std::vector<Saved> m_saved;
    std::vector<std::uint32_t> m_created; ///< vertices insert_segment() created (crossings)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> m_new_edges;
    bool m_list_new_edges = true; ///< false while the build inserts the input
    std::vector<std::uint32_t> m_ring;
    std::vector<cdt::Face_handle> m_walk;
    std::vector<cdt::Face_handle> m_hub_faces;
    mutable std::vector<OwnerRef> m_refs;
};

double distance_point_segment(double px, double py, double ax, double ay, double bx, double by);
/// The squared distance from p to the segment a-b (what the snapper compares). Inline: the
/// initial scan asks it three times per face (a call was 1.8 % of a run's instructions); the
/// same operations in the same order wherever it is compiled (-ffp-contract=off, no fast-math).
inline double squared_distance_point_segment(double px, double py, double ax, double ay, double bx, double by)
{
    const double dx = bx - ax;
    const double dy = by - ay;
    const double len2 = dx * dx + dy * dy;
    const double s = std::clamp(len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0, 0.0, 1.0);
    const double ex = px - (ax + s * dx);
    const double ey = py - (ay + s * dy);
    return ex * ex + ey * ey;
}

} // namespace trisnap::detail
