#include "core/extraction.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace trisnap::detail {
namespace {

struct HalfEdge {
    cdt::Face_handle face;
    int index;
    std::uint32_t from() const { return face->vertex(cdt::Triangulation::ccw(index))->info().id; }
};

Coord output_coord(const Mesh& mesh, std::uint32_t v, const ExtractOptions& o)
{
    const VertexRecord& r = mesh.vertex(v);
    Coord c{r.x, r.y, o.has_z ? r.z : std::nan("")};
    if (o.grid > 0) c.x = std::round(c.x / o.grid) * o.grid, c.y = std::round(c.y / o.grid) * o.grid;
    c.x += 0.0, c.y += 0.0; // no negative zeros in the output
    return c;
}

bool coord_less(const Coord& a, const Coord& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; }

Path make_ring(const Mesh& mesh, const std::vector<std::uint32_t>& ids, const ExtractOptions& o)
{
    Path ring;
    for (std::uint32_t v : ids) ring.push_back(output_coord(mesh, v, o));
    const auto first = std::min_element(ring.begin(), ring.end(), coord_less);
    std::rotate(ring.begin(), first, ring.end());
    ring.push_back(ring.front());
    return ring;
}

double signed_area(const Mesh& mesh, const std::vector<std::uint32_t>& ids)
{
    double a = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const VertexRecord &p = mesh.vertex(ids[i]), &q = mesh.vertex(ids[(i + 1) % ids.size()]);
        a += p.x * q.y - q.x * p.y;
    }
    return 0.5 * a;
}

class PolygonTracer {
public:
    PolygonTracer(Mesh& mesh, const std::vector<cdt::Face_handle>& faces) : m_mesh(mesh), m_faces(faces) {}

    Geometry run(const ExtractOptions& options);

private:
    bool inside(cdt::Face_handle f) const { return f->info().stamp == m_stamp; }
    std::uint32_t find(std::uint32_t x)
    {
        while (m_parent[x] != x) x = m_parent[x] = m_parent[m_parent[x]];
        return x;
    }
    void mark_and_group();
    void collect_half_edges();
    std::size_t next(std::size_t h) const;
    void trace(std::size_t start);
    void emit(std::vector<std::size_t> loop);

    Mesh& m_mesh;
    const std::vector<cdt::Face_handle>& m_faces;
    std::uint32_t m_stamp = 0;
    std::vector<std::uint32_t> m_parent;
    std::vector<HalfEdge> m_half;
    std::unordered_map<const void*, std::array<std::int32_t, 3>> m_half_of;
    std::vector<bool> m_used;
    struct Loop { std::vector<std::uint32_t> ids; std::uint32_t group; double area; };
    std::vector<Loop> m_loops;
};

void PolygonTracer::mark_and_group()
{
    m_stamp = m_mesh.fresh_stamp();
    for (std::uint32_t k = 0; k < m_faces.size(); ++k) {
        m_faces[k]->info().stamp = m_stamp;
        m_faces[k]->info().scratch = k;
    }
    m_parent.resize(m_faces.size());
    std::iota(m_parent.begin(), m_parent.end(), 0u);
    for (const cdt::Face_handle f : m_faces)
        for (int i = 0; i < 3; ++i)
            if (inside(f->neighbor(i))) m_parent[find(f->info().scratch)] = find(f->neighbor(i)->info().scratch);
}

void PolygonTracer::collect_half_edges()
{
    for (const cdt::Face_handle f : m_faces) {
        for (int i = 0; i < 3; ++i) {
            if (inside(f->neighbor(i))) continue;
            auto [it, added] = m_half_of.try_emplace(&*f, std::array<std::int32_t, 3>{-1, -1, -1});
            it->second[i] = static_cast<std::int32_t>(m_half.size());
            m_half.push_back(HalfEdge{f, i});
        }
    }
    m_used.assign(m_half.size(), false);
}

// The boundary edge that leaves the end vertex of h within the same sector of the feature.
std::size_t PolygonTracer::next(std::size_t h) const
{
    const cdt::Vertex_handle v = m_half[h].face->vertex(cdt::Triangulation::cw(m_half[h].index));
    cdt::Face_handle g = m_half[h].face;
    for (;;) {
        const int j = cdt::Triangulation::cw(g->index(v));
        if (!inside(g->neighbor(j))) return static_cast<std::size_t>(m_half_of.at(&*g)[j]);
        g = g->neighbor(j);
    }
}

void PolygonTracer::trace(std::size_t start)
{
    std::vector<std::size_t> seq;
    std::unordered_map<std::uint32_t, std::size_t> pos;
    for (std::size_t h = start; !m_used[h]; h = next(h)) {
        m_used[h] = true;
        const std::uint32_t v = m_half[h].from();
        if (auto it = pos.find(v); it != pos.end()) { // cut the loop that closes at v
            const std::size_t k = it->second;
            std::vector<std::size_t> loop(seq.begin() + static_cast<std::ptrdiff_t>(k), seq.end());
            for (std::size_t q = k; q < seq.size(); ++q) pos.erase(m_half[seq[q]].from());
            seq.resize(k);
            emit(std::move(loop));
        }
        pos[v] = seq.size();
        seq.push_back(h);
    }
    if (!seq.empty()) emit(std::move(seq));
}

void PolygonTracer::emit(std::vector<std::size_t> loop)
{
    Loop l;
    for (std::size_t h : loop) l.ids.push_back(m_half[h].from());
    l.group = find(m_half[loop.front()].face->info().scratch);
    l.area = signed_area(m_mesh, l.ids);
    m_loops.push_back(std::move(l));
}

Geometry PolygonTracer::run(const ExtractOptions& options)
{
    Geometry g;
    g.has_z = options.has_z;
    if (m_faces.empty()) return g;
    mark_and_group();
    collect_half_edges();
    for (std::size_t h = 0; h < m_half.size(); ++h)
        if (!m_used[h]) trace(h);
    // One shell per group (the largest counter-clockwise loop, should there ever be two);
    // holes join the shell of their group.
    std::unordered_map<std::uint32_t, std::pair<std::size_t, double>> shell_of;
    for (const Loop& l : m_loops) {
        if (l.area <= 0) continue;
        auto [it, added] = shell_of.try_emplace(l.group, g.polygons.size(), l.area);
        if (!added && l.area > it->second.second) it->second = {g.polygons.size(), l.area};
        g.polygons.push_back(Polygon{{make_ring(m_mesh, l.ids, options)}});
    }
    for (const Loop& l : m_loops) {
        if (l.area >= 0) continue;
        auto it = shell_of.find(l.group);
        if (it != shell_of.end()) g.polygons[it->second.first].rings.push_back(make_ring(m_mesh, l.ids, options));
    }
    for (Polygon& p : g.polygons)
        std::sort(p.rings.begin() + 1, p.rings.end(), [](const Path& a, const Path& b) { return coord_less(a[0], b[0]); });
    std::sort(g.polygons.begin(), g.polygons.end(),
              [](const Polygon& a, const Polygon& b) { return coord_less(a.rings[0][0], b.rings[0][0]); });
    g.type = g.polygons.size() == 1 ? Geometry::Type::Polygon : Geometry::Type::MultiPolygon;
    if (g.polygons.empty()) g.type = Geometry::Type::Empty;
    return g;
}

} // namespace

Geometry extract_polygons(Mesh& mesh, const std::vector<cdt::Face_handle>& faces,
                          const ExtractOptions& options)
{
    return PolygonTracer(mesh, faces).run(options);
}

} // namespace trisnap::detail
