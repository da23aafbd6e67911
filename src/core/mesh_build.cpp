// Building the triangulation: points in a canonical order, one constraint per input edge (split
// at crossings and at vertices lying on it by insert_segment, mesh_insert.cpp).
#include "core/mesh.hpp"

#include "core/input_cleaning.hpp"

#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/spatial_sort.h>
#include <boost/property_map/property_map.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace trisnap::detail {
namespace {

struct InputPoint {
    double x, y, z;
    std::size_t at; ///< its place in Mesh::m_input_ids (features in order, rings then lines, rings closed)
};

bool xy_less(const InputPoint& a, const InputPoint& b)
{
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z || (std::isnan(b.z) && !std::isnan(a.z));
}

std::vector<InputPoint> gather_points(const std::vector<CleanFeature>& features, std::vector<std::uint32_t>& input_ids,
                                      std::vector<std::size_t>& first, std::vector<std::uint32_t>& path_sizes)
{
    std::size_t n = 0;
    for (const CleanFeature& cf : features) {
        for (const CleanRing& r : cf.rings) n += r.points.size();
        for (const auto& l : cf.lines) n += l.size();
    }
    // Vertex ids and owner features are 32-bit (Owner keeps a feature in 31 bits); crossings
    // take ids after the input points, so leave them room.
    if (n >= (std::size_t{1} << 31) || features.size() >= (std::size_t{1} << 31)) {
        throw std::length_error("more than 2^31 input points or features in one triangulation: split the layer in tiles");
    }
    std::vector<InputPoint> pts;
    pts.reserve(n);
    first.assign(1, 0);
    first.reserve(features.size() + 1);
    path_sizes.clear();
    std::size_t place = 0; // in input_ids: a ring's closing place is filled in by insert_points
    for (const CleanFeature& cf : features) {
        auto add = [&](const Coord& c) { pts.push_back({c.x, c.y, c.z, place++}); };
        for (const CleanRing& r : cf.rings) {
            std::for_each(r.points.begin(), r.points.end(), add);
            ++place;
            path_sizes.push_back(static_cast<std::uint32_t>(r.points.size()));
        }
        for (const auto& l : cf.lines) {
            std::for_each(l.begin(), l.end(), add);
            path_sizes.push_back(static_cast<std::uint32_t>(l.size()));
        }
        first.push_back(place);
    }
    input_ids.assign(place, cdt::k_no_id);
    std::sort(pts.begin(), pts.end(), xy_less);
    return pts;
}

// Mean of the defined z values of one run of equal (x, y); NaN when none is defined.
double mean_z(std::vector<InputPoint>::const_iterator first, std::vector<InputPoint>::const_iterator last)
{
    double sum = 0;
    int n = 0;
    for (auto it = first; it != last; ++it)
        if (!std::isnan(it->z)) sum += it->z, ++n;
    return n ? sum / n : std::nan("");
}

} // namespace

Mesh::Mesh(const std::vector<CleanFeature>& features, double reach, WorkMeter* meter)
{
    Outlines outlines;
    build(features, reach, meter, outlines, nullptr);
}

Mesh::Mesh(std::vector<CleanFeature>&& features, double reach, WorkMeter* meter, Outlines& outlines)
{
    build(features, reach, meter, outlines, &features);
}

void Mesh::build(const std::vector<CleanFeature>& features, double reach, WorkMeter* meter, Outlines& outlines,
                 std::vector<CleanFeature>* release)
{
    // Only the snapper's edits need the list of new edges: the build would list every
    // constraint (13 MB on Andorra x43, at the build's peak).
    m_list_new_edges = false;
    const std::vector<std::uint32_t> path_sizes = insert_points(features, reach, meter, outlines, release);
    const std::size_t first_created = m_vertices.size();
    insert_constraints(outlines.features, path_sizes, meter); // `features` may be freed by now
    register_created_vertices(first_created);
    m_list_new_edges = true;
}

// Distinct points get ids in lexicographic (x, y) order; they are inserted in CGAL's spatial
// sort of that order. Both orders depend only on the set of points, not on feature order.
// Four unconstrained corners far outside the data keep the triangulation two-dimensional
// whatever the input (one line, collinear rings, everything merging into one point), so the
// walks, the labelling and CGAL's removal never meet a degenerate triangulation. They are more
// than `reach` from every input point, so no snapping event ever involves them, and being
// unconstrained they are never on an output boundary.
std::vector<std::pair<cdt::Point, std::uint32_t>> frame_points(const std::vector<InputPoint>& pts,
                                                               double reach, std::uint32_t first_id)
{
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (!pts.empty()) {
        x0 = x1 = pts.front().x, y0 = y1 = pts.front().y;
        for (const InputPoint& p : pts)
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
    const double m = std::max({x1 - x0, y1 - y0, 4.0 * reach, 1.0});
    std::vector<std::pair<cdt::Point, std::uint32_t>> out;
    const double xs[2] = {x0 - m, x1 + m}, ys[2] = {y0 - m, y1 + m};
    for (int i = 0; i < 4; ++i) out.emplace_back(cdt::Point(xs[i / 2], ys[(i / 2) ^ (i % 2)]), first_id + i);
    return out;
}

// A vertex record's point and id, what CGAL's spatial sort moves: sorting ids and reading
// the points through them missed the cache on every comparison (Andorra x43 untiled: the sort
// was ~5 % of the run). The sort makes the same comparisons in the same order on the same
// points, so it leaves the ids in the same order either way.
struct SortPoint {
    double x;
    double y;
    std::uint32_t id;
};

struct SortPointMap {
    using key_type = SortPoint;
    using value_type = cdt::Point;
    using reference = cdt::Point;
    using category = boost::readable_property_map_tag;
    friend cdt::Point get(const SortPointMap&, const SortPoint& p) { return {p.x, p.y}; }
};

// CGAL's Constrained_Delaunay_triangulation_2::flip_around(va) while no edge is constrained:
// the same flips in the same order (its propagating_flip, recursive to a depth of 100 and then
// its non-recursive version, with its is_flipable test), each done by the data structure's
// flip alone. CGAL's constrained flip saves the four wing edges' flags around it and copies
// them back: with no constraint anywhere they are all "not constrained" before and after.
// Its twin with constraints and a flip budget is Mesh::propagate_flip (mesh_hubs.cpp), used by
// the snapper's edits. One shared version (template on the plain flip, CGAL's is_flipable, the
// budget and depth checks) was tried in the review: 1,104.6 -> 1,131-1,141 M instructions on
// Natural Earth's countries, most of this change's gain; so the build keeps its own.
class BuildFlips {
public:
    explicit BuildFlips(cdt::Triangulation& tri) : m_tri(tri) {}

    void around(cdt::Vertex_handle va)
    {
        if (m_tri.dimension() <= 1) return;
        cdt::Face_handle f = va->face();
        const cdt::Face_handle start = f;
        cdt::Face_handle next;
        do {
            const int i = f->index(va);
            next = f->neighbor(cdt::Triangulation::ccw(i));
            propagate(f, i, 0);
            f = next;
        } while (next != start);
    }

private:
    bool flipable(cdt::Face_handle f, int i) const
    {
        const cdt::Face_handle ni = f->neighbor(i);
        if (m_tri.is_infinite(f) || m_tri.is_infinite(ni)) return false;
        return m_tri.side_of_oriented_circle(ni, f->vertex(i)->point(), true) == CGAL::ON_POSITIVE_SIDE;
    }

    void propagate(cdt::Face_handle f, int i, int depth)
    {
        if (!flipable(f, i)) return;
        if (depth == 100) {
            propagate_without_recursion(f, i);
            return;
        }
        const cdt::Face_handle ni = f->neighbor(i);
        m_tri.tds().flip(f, i);
        propagate(f, i, depth + 1);
        i = ni->index(f->vertex(i));
        propagate(ni, i, depth + 1);
    }

    void propagate_without_recursion(cdt::Face_handle f, int i)
    {
        std::vector<cdt::Triangulation::Edge> edges;
        const cdt::Vertex_handle vp = f->vertex(i);
        edges.emplace_back(f, i);
        while (!edges.empty()) {
            f = edges.back().first;
            i = edges.back().second;
            const cdt::Face_handle ni = f->neighbor(i);
            m_tri.tds().flip(f, i);
            if (!flipable(f, i)) edges.pop_back();
            i = ni->index(vp);
            if (flipable(ni, i)) edges.emplace_back(ni, i);
        }
    }

    cdt::Triangulation& m_tri;
};

std::vector<std::uint32_t> Mesh::insert_points(const std::vector<CleanFeature>& features, double reach,
                                               WorkMeter* meter, Outlines& outlines, std::vector<CleanFeature>* release)
{
    if (meter) meter->begin(WorkMeter::Step::points);
    std::vector<std::uint32_t> path_sizes;
    std::vector<InputPoint> pts = gather_points(features, m_input_ids, m_input_first, path_sizes);
    outlines = make_outlines(features);
    if (release != nullptr) {
        // `pts` holds every coordinate now, and the records will (vertices never move).
        std::vector<CleanFeature>().swap(*release);
    }
    std::size_t distinct = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        distinct += i == 0 || pts[i].x != pts[i - 1].x || pts[i].y != pts[i - 1].y ? 1 : 0;
    }
    // The records are filled straight from the sorted points, which go before CGAL's vertices
    // and faces are made (the build's copies of the points peaked above the snapper's tables).
    // A few per cent of room for the vertices crossings and edits add: the vectors would
    // otherwise double at the first one (Andorra x43 untiled: 1.6 M records, 100 MB unused).
    // Past that room they double: growing by less left more freed blocks behind in the heap,
    // which the process keeps (src/app/allocator.hpp): Natural Earth land at 2 km, 150 k
    // merges, peaked 41 MiB higher growing by an eighth.
    const std::size_t total = distinct + frame_vertices;
    const std::size_t room = with_room(total);
    m_vertices.reserve(room);
    m_forward.reserve(room);
    m_vertices.resize(total);
    // The points go to CGAL in `order`; the slots learn where their vertices are as they go in.
    std::vector<SortPoint> order(total);
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < pts.size(); ++id) {
        std::size_t j = i;
        while (j < pts.size() && pts[j].x == pts[i].x && pts[j].y == pts[i].y) ++j;
        for (std::size_t k = i; k < j; ++k) m_input_ids[pts[k].at] = id;
        order[id] = SortPoint{pts[i].x, pts[i].y, id};
        set_z(id, mean_z(pts.begin() + i, pts.begin() + j));
        i = j;
    }
    m_input_points = id;
    close_rings(outlines.features, path_sizes);
    for (const auto& [p, corner] : frame_points(pts, reach, id)) {
        order[corner] = SortPoint{p.x(), p.y(), corner};
    }
    std::vector<InputPoint>().swap(pts);
    // Every later vertex lies inside the frame, so its corners bound the coordinates' size.
    double largest = 0;
    for (const SortPoint& p : order) {
        largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
    }
    m_ulp_margin = 64 * (std::nextafter(largest, std::numeric_limits<double>::infinity()) - largest);
    CGAL::spatial_sort(order.begin(), order.end(), CGAL::Spatial_sort_traits_adapter_2<cdt::Kernel, SortPointMap>());
    // No constraint exists yet: each point goes in as CGAL's constrained insert would put it
    // (locate, the plain triangulation's insertion, then the Delaunay flips around it) without
    // the bookkeeping of constraint flags around the new vertex and around each flip, which can
    // only copy "not constrained" here (BuildFlips). The same operations on the same faces:
    // the same triangulation, face for face.
    cdt::Face_handle hint;
    std::size_t inserted = 0;
    BuildFlips flips(m_tri);
    for (const SortPoint& p : order) {
        const cdt::Point pt(p.x, p.y);
        cdt::Triangulation::Locate_type lt{};
        int li = 0;
        const cdt::Face_handle loc = m_tri.locate(pt, lt, li, hint);
        const cdt::Vertex_handle h = static_cast<cdt::CtBase::Triangulation&>(m_tri).insert(pt, lt, loc, li);
        if constexpr (cdt::k_delaunay) {
            flips.around(h);
        }
        m_vertices[p.id].at = address(h);
        h->info().id = p.id;
        hint = h->face();
        if (meter && (++inserted & 1023) == 0) meter->advance(inserted, order.size());
    }
    std::vector<SortPoint>().swap(order);
    m_forward.assign(total, cdt::k_no_id);
    return path_sizes;
}

void Mesh::close_rings(const std::vector<Outline>& features, const std::vector<std::uint32_t>& path_sizes)
{
    std::size_t p = 0;
    for (std::size_t f = 0; f < features.size(); ++f) {
        std::size_t base = m_input_first[f];
        for (std::uint32_t k = 0; k < features[f].paths; ++k, ++p) {
            const std::size_t n = path_sizes[p];
            if (features[f].polygonal) { // a polygon's paths are rings, a line feature's lines
                m_input_ids[base + n] = m_input_ids[base];
                ++base;
            }
            base += n;
        }
        assert(base == m_input_first[f + 1]);
    }
}

// Features are inserted in (id, index) order so crossings are found in an order that does not
// depend on how the caller ordered its features.
void Mesh::insert_constraints(const std::vector<Outline>& features, const std::vector<std::uint32_t>& path_sizes,
                              WorkMeter* meter)
{
    // Each feature's first path in path_sizes (features in input order there).
    std::vector<std::size_t> first_path(features.size() + 1, 0);
    for (std::size_t f = 0; f < features.size(); ++f) {
        first_path[f + 1] = first_path[f] + features[f].paths;
    }
    if (meter) meter->begin(WorkMeter::Step::constraints);
    std::size_t total_edges = 0; // a ring has as many edges as points, a line one fewer
    for (std::size_t f = 0; f < features.size(); ++f) {
        for (std::size_t p = first_path[f]; p < first_path[f + 1]; ++p) total_edges += path_sizes[p] - (features[f].polygonal ? 0 : 1);
    }
    std::size_t edges_done = 0;
    m_owners.reserve(total_edges); // one per input edge, added here only
    m_edge_owners.reserve(total_edges, with_room(total_edges)); // crossings and splits add entries
    std::vector<std::uint32_t> order(features.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return features[a].id != features[b].id ? features[a].id < features[b].id : a < b;
    });
    for (std::uint32_t f : order) {
        std::size_t base = m_input_first[f];
        auto add_path = [&](std::size_t n, bool closed, bool line) {
            const std::size_t edges = closed ? n : n - 1; // a ring's last edge ends at its closing place
            for (std::size_t i = 0; i < edges; ++i) {
                const Owner o{f, line, static_cast<std::uint32_t>(base + i)};
                m_owners.push_back(o);
                const OwnerRef ref{static_cast<std::uint32_t>(m_owners.size() - 1), true};
                insert_segment(handle(owner_from(o)), handle(owner_to(o)), std::span(&ref, 1));
                if (meter && (++edges_done & 255) == 0) meter->advance(edges_done, total_edges);
            }
            base += closed ? n + 1 : n;
        };
        const Outline& o = features[f];
        const std::uint32_t* sizes = path_sizes.data() + first_path[f];
        for (std::size_t p = 0; p < o.paths; ++p) {
            add_path(sizes[p], o.polygonal, !o.polygonal); // a polygon's paths are rings, a line feature's lines
        }
    }
}

// Crossing vertices were numbered as they were created; they get ids after the input points in
// coordinate order instead (then nothing depends on the order crossings were found in), and the
// z of the input edges through them.
void Mesh::register_created_vertices(std::size_t first_created)
{
    const std::size_t n = m_vertices.size();
    std::vector<std::uint32_t> created(n - first_created);
    std::iota(created.begin(), created.end(), static_cast<std::uint32_t>(first_created));
    std::sort(created.begin(), created.end(), [&](std::uint32_t a, std::uint32_t b) {
        const Xy pa = xy(a), pb = xy(b);
        return std::tie(pa.x, pa.y) < std::tie(pb.x, pb.y);
    });
    std::vector<std::uint32_t> rename(n);
    std::iota(rename.begin(), rename.end(), 0u);
    std::vector<VertexSlot> records(created.size());
    for (std::size_t k = 0; k < created.size(); ++k) {
        rename[created[k]] = static_cast<std::uint32_t>(first_created + k);
        records[k] = std::move(m_vertices[created[k]]);
    }
    for (std::size_t k = 0; k < created.size(); ++k) {
        m_vertices[first_created + k] = std::move(records[k]);
        handle(static_cast<std::uint32_t>(first_created + k))->info().id = static_cast<std::uint32_t>(first_created + k);
    }
    m_edge_owners.rename(rename);
    for (std::size_t id = first_created; id < n; ++id) {
        m_vertices[id].weight = 1;
        set_z(static_cast<std::uint32_t>(id), interpolated_z(handle(static_cast<std::uint32_t>(id))));
    }
    m_intersections += created.size();
    m_created.clear();
}

std::uint32_t Mesh::add_record(cdt::Vertex_handle h, double z)
{
    const auto id = static_cast<std::uint32_t>(m_vertices.size());
    h->info().id = id;
    VertexSlot r;
    r.at = address(h);
    m_vertices.push_back(r);
    m_forward.push_back(cdt::k_no_id);
    if (!m_z.empty()) {
        m_z.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    set_z(id, z);
    return id;
}

void Mesh::set_z(std::uint32_t id, double z)
{
    if (m_z.empty()) {
        if (std::isnan(z)) {
            return;
        }
        m_z.reserve(m_vertices.capacity());
        m_z.assign(m_vertices.size(), std::numeric_limits<double>::quiet_NaN());
    }
    m_z[id] = z;
}

// A vertex created on constraints takes the z of each input edge through it, interpolated by
// distance between that edge's ends (where they are now); where several input edges with z
// meet, the mean of their interpolations.
double Mesh::interpolated_z(cdt::Vertex_handle h)
{
    if (m_z.empty()) {
        return std::numeric_limits<double>::quiet_NaN(); // no input point has a z
    }
    const double x = h->point().x();
    const double y = h->point().y();
    double sum = 0;
    int n = 0;
    std::vector<OwnerRef> refs;
    auto vc = m_tri.incident_vertices(h);
    const auto done = vc;
    do {
        if (!m_tri.is_infinite(vc)) {
            m_edge_owners.get(id(h), id(vc), refs);
        }
    } while (++vc != done);
    // Summed in owner order, not in the order of the walk round h, which starts at whatever face
    // CGAL keeps for it (another in a tile): three or more z values add up differently in the
    // last bit in another order.
    std::sort(refs.begin(), refs.end(), [](const OwnerRef& a, const OwnerRef& b) { return a.owner < b.owner; });
    for (std::size_t k = 0; k < refs.size(); ++k) {
        if (k > 0 && refs[k].owner == refs[k - 1].owner) {
            continue;
        }
        const OwnerRef& ref = refs[k];
        const std::uint32_t a = current(owner_from(m_owners[ref.owner]));
        const std::uint32_t b = current(owner_to(m_owners[ref.owner]));
        const Xy ra = xy(a);
        const Xy rb = xy(b);
        const double la = std::hypot(x - ra.x, y - ra.y);
        const double lb = std::hypot(x - rb.x, y - rb.y);
        const double za = m_z[a];
        const double z = la + lb > 0 ? za + (m_z[b] - za) * la / (la + lb) : za;
        if (!std::isnan(z)) {
            sum += z;
            ++n;
        }
    }
    return n ? sum / n : std::nan("");
}

std::uint32_t Mesh::current(std::uint32_t id)
{
    std::uint32_t root = id;
    while (m_forward[root] != cdt::k_no_id) root = m_forward[root];
    while (m_forward[id] != cdt::k_no_id) {
        const std::uint32_t next = m_forward[id];
        m_forward[id] = root;
        id = next;
    }
    return root;
}

void Mesh::polygon_ownership(std::span<const OwnerRef> refs, std::vector<FeatureCount>& out) const
{
    out.clear();
    // One or two owners (nearly every edge: a boundary, or two neighbours' shared one): the
    // same sorted counts without the sort's call.
    if (refs.size() <= 2) {
        for (const OwnerRef& r : refs) {
            const Owner& o = m_owners[r.owner];
            if (o.line) {
                continue;
            }
            if (!out.empty() && out[0].feature == o.feature) {
                ++out[0].times;
            } else {
                out.push_back(FeatureCount{o.feature, 1});
            }
        }
        if (out.size() == 2 && out[1].feature < out[0].feature) {
            std::swap(out[0], out[1]);
        }
        return;
    }
    for (const OwnerRef& r : refs) {
        const Owner& o = m_owners[r.owner];
        if (!o.line) {
            out.push_back(FeatureCount{o.feature, 1});
        }
    }
    std::sort(out.begin(), out.end(), [](const FeatureCount& a, const FeatureCount& b) { return a.feature < b.feature; });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < out.size(); ++k) {
        if (kept > 0 && out[kept - 1].feature == out[k].feature) {
            ++out[kept - 1].times;
        } else {
            out[kept++] = out[k];
        }
    }
    out.resize(kept);
}

void Mesh::owners_of_edge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const
{
    out.clear();
    m_refs.clear();
    m_edge_owners.get(a, b, m_refs);
    for (const OwnerRef& r : m_refs) {
        out.push_back(r.owner);
    }
}

void Mesh::release_owners()
{
    std::vector<Owner>().swap(m_owners);
    m_edge_owners = EdgeOwners{};
    std::vector<OwnerRef>().swap(m_arena);
    std::vector<OwnerRef>().swap(m_refs);
}

void Mesh::release_triangulation()
{
    release_search_scratch();
    release_owners();
    // Every vertex's point to m_kept first (one allocation of the size it needs), then CGAL's.
    std::size_t live = 0;
    for (const VertexSlot& s : m_vertices) live += s.in_triangulation() ? 1 : 0;
    m_kept.reserve(m_kept.size() + live);
    for (std::uint32_t id = 0; id < m_vertices.size(); ++id) {
        if (m_vertices[id].in_triangulation()) keep_point(id);
    }
    m_tri.clear(); // CGAL's containers free their blocks
    std::vector<Job>().swap(m_jobs);
    std::vector<Saved>().swap(m_saved);
    std::vector<cdt::Face_handle>().swap(m_walk);
    std::vector<cdt::Face_handle>().swap(m_hub_faces);
}

void Mesh::keep_point(std::uint32_t id)
{
    VertexSlot& s = m_vertices[id];
    assert(s.in_triangulation());
    const Xy p = xy(id);
    s.at = (static_cast<std::uintptr_t>(m_kept.size()) << 1) | 1;
    m_kept.push_back(p);
}

} // namespace trisnap::detail
