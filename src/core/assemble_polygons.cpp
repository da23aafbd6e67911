// Rings from directed boundary edges (see assemble.hpp): tracing with sector rule, loop cutting,
// exact orientation of loops, holes to the innermost shell holding them.
#include "core/assemble.hpp"
#include "core/assemble_detail.hpp"
#include "core/predicates.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

namespace trisnap {
namespace {

using detail::EdgeKeyLess;
using detail::same_xy;

constexpr std::size_t k_none = std::numeric_limits<std::size_t>::max(); ///< no loop

/// An edge or vertex of one feature's boundary: 32 bits, half a size_t in the assembler's five
/// tables (Natural Earth's land: 0.4 M edges in one feature); the constructor refuses more.
using Index = std::uint32_t;
constexpr Index k_no = std::numeric_limits<Index>::max(); ///< no vertex (an open end), no position

struct Loop {
    std::vector<Coord> pts;
    double xmin = 0, ymin = 0, xmax = 0, ymax = 0;
    bool shell = false;
};

bool box_contains(const Loop& outer, const Loop& inner)
{
    return outer.xmin <= inner.xmin && inner.xmax <= outer.xmax && outer.ymin <= inner.ymin &&
           inner.ymax <= outer.ymax;
}

// A loop's edges bucketed by horizontal strips, and its vertices sorted, built once per shell
// that has to be tested: a point test then looks at one strip instead of the whole ring.
class RingIndex {
public:
    explicit RingIndex(const Loop& loop);
    int locate(const Coord& p) const;
    bool has_vertex(const Coord& p) const { return std::binary_search(m_sorted.begin(), m_sorted.end(), p, xy_less); }

private:
    std::size_t strip(double y) const;

    const std::vector<Coord>& m_pts;
    std::vector<Coord> m_sorted;
    double m_y0 = 0;
    double m_y1 = 0;
    double m_step = 1;
    std::vector<std::vector<std::uint32_t>> m_strips;
};

RingIndex::RingIndex(const Loop& loop) : m_pts(loop.pts), m_sorted(loop.pts), m_y0(loop.ymin), m_y1(loop.ymax)
{
    std::sort(m_sorted.begin(), m_sorted.end(), xy_less);
    const std::size_t n = m_pts.size();
    m_strips.resize(std::max<std::size_t>(1, n / 8));
    m_step = (m_y1 - m_y0) / static_cast<double>(m_strips.size());
    if (!(m_step > 0)) {
        m_strips.resize(1);
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const Coord& a = m_pts[i];
        const Coord& b = m_pts[(i + 1) % n];
        for (std::size_t k = strip(std::min(a.y, b.y)); k <= strip(std::max(a.y, b.y)); ++k) {
            m_strips[k].push_back(i);
        }
    }
}

std::size_t RingIndex::strip(double y) const
{
    if (m_strips.size() == 1) {
        return 0;
    }
    const double k = std::floor((y - m_y0) / m_step);
    return static_cast<std::size_t>(std::clamp(k, 0.0, static_cast<double>(m_strips.size() - 1)));
}

// Every edge whose y-range holds p.y is in p's strip, so the crossing number is complete.
int RingIndex::locate(const Coord& p) const
{
    if (p.y < m_y0 || p.y > m_y1) {
        return -1;
    }
    bool inside = false;
    const std::size_t n = m_pts.size();
    for (std::uint32_t i : m_strips[strip(p.y)]) {
        const RayStep step = ray_step(m_pts[i], m_pts[(i + 1) % n], p);
        if (step == RayStep::on_segment) {
            return 0;
        }
        inside ^= step == RayStep::crosses;
    }
    return inside ? 1 : -1;
}

// Is direction u->v strictly inside the interior sector of a counter-clockwise ring at its
// vertex u (between u->next and u->prev, counter-clockwise)?
bool in_interior_sector(const Coord& prev, const Coord& u, const Coord& next, const Coord& v)
{
    if (orientation(u, next, prev) > 0) {
        return orientation(u, next, v) > 0 && orientation(u, v, prev) > 0;
    }
    return !(orientation(u, prev, v) >= 0 && orientation(u, v, next) >= 0);
}

class PolygonAssembler {
public:
    PolygonAssembler(std::vector<DirectedEdge> edges, bool has_z);
    Geometry run(std::vector<Polygon> finished);

private:
    void index_vertices();
    Index next(Index e) const;
    void trace(Index start);
    void emit(std::size_t from);
    std::size_t holder_of(const Loop& hole);
    bool inside(std::size_t shell, const Loop& loop);
    const RingIndex& index_of(std::size_t shell);

    std::vector<DirectedEdge> m_edges;
    bool m_has_z;
    std::vector<Index> m_vertex_of_start; ///< edge -> index of its start vertex
    std::vector<Index> m_vertex_of_end;   ///< edge -> index of its end vertex (k_no: open)
    std::vector<Index> m_first;           ///< vertex -> first position in m_out
    std::vector<Index> m_out;             ///< edge indices by start vertex, then by angle
    std::vector<bool> m_used;
    std::vector<Index> m_pos;             ///< vertex -> position in the current trace (k_no: none)
    std::vector<Index> m_seq;             ///< the current trace's edges
    std::vector<Loop> m_loops;
    std::vector<std::unique_ptr<RingIndex>> m_index; ///< per loop, built on demand
};

PolygonAssembler::PolygonAssembler(std::vector<DirectedEdge> edges, bool has_z)
    : m_edges(std::move(edges)), m_has_z(has_z)
{
    std::erase_if(m_edges, [](const DirectedEdge& e) { return same_xy(e.a, e.b); });
    std::sort(m_edges.begin(), m_edges.end(), EdgeKeyLess{});
    m_edges.erase(std::unique(m_edges.begin(), m_edges.end(), detail::edge_key_equal), m_edges.end());
    if (m_edges.size() >= k_no) {
        throw std::length_error("a feature with " + std::to_string(m_edges.size()) +
                                " boundary edges: more than one feature's output can hold (2^32 - 1)");
    }
}

// Edges are sorted by start point, so each vertex's out-edges are one run; within it they are
// ordered counter-clockwise around the vertex.
void PolygonAssembler::index_vertices()
{
    const auto n = static_cast<Index>(m_edges.size());
    m_vertex_of_start.resize(n);
    std::vector<Coord> vertices;
    for (Index e = 0; e < n; ++e) {
        if (vertices.empty() || !same_xy(vertices.back(), m_edges[e].a)) {
            vertices.push_back(m_edges[e].a);
            m_first.push_back(e);
        }
        m_vertex_of_start[e] = static_cast<Index>(vertices.size() - 1);
    }
    m_first.push_back(n);
    m_out.resize(n);
    std::iota(m_out.begin(), m_out.end(), Index{0});
    for (std::size_t v = 0; v + 1 < m_first.size(); ++v) {
        if (m_first[v + 1] - m_first[v] > 1) { // most vertices have one out-edge
            std::sort(m_out.begin() + m_first[v], m_out.begin() + m_first[v + 1],
                      [&](Index i, Index j) { return direction_less(vertices[v], m_edges[i].b, m_edges[j].b); });
        }
    }
    // Each edge's end among the (distinct) start vertices, through a hash table of them: a
    // binary search per edge was 2.5 % of a run's instructions on Natural Earth's countries.
    // Coordinates are hashed as 0.0 + value, so -0.0 finds 0.0 as same_xy does.
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v + 0.0); };
    const auto hash = [&](const Coord& c) {
        const std::uint64_t h = (bits(c.x) * 0x9E3779B97F4A7C15ull) ^ (bits(c.y) + 0x632BE59BD9B4E019ull);
        return (h ^ (h >> 29)) * 0xBF58476D1CE4E5B9ull;
    };
    std::size_t slots = 16;
    while (slots < 2 * vertices.size()) slots *= 2;
    std::vector<Index> table(slots, k_no);
    for (Index v = 0; v < vertices.size(); ++v) {
        std::size_t s = hash(vertices[v]) & (slots - 1);
        while (table[s] != k_no) s = (s + 1) & (slots - 1);
        table[s] = v;
    }
    m_vertex_of_end.assign(n, k_no);
    for (Index e = 0; e < n; ++e) {
        const Coord& b = m_edges[e].b;
        for (std::size_t s = hash(b) & (slots - 1); table[s] != k_no; s = (s + 1) & (slots - 1)) {
            if (same_xy(vertices[table[s]], b)) {
                m_vertex_of_end[e] = table[s];
                break;
            }
        }
    }
    m_used.assign(n, false);
    m_pos.assign(vertices.size(), k_no);
}

// The edge leaving the end of e within the same sector of the feature: among the out-edges
// (counter-clockwise), the last one before the direction back along e, else the last overall.
Index PolygonAssembler::next(Index e) const
{
    const Index v = m_vertex_of_end[e];
    if (v == k_no) {
        return k_no;
    }
    const auto lo = m_out.begin() + m_first[v];
    const auto hi = m_out.begin() + m_first[v + 1];
    if (hi - lo == 1) {
        return *lo; // the only out-edge, whichever side of it the way back lies (most vertices)
    }
    const Coord& at = m_edges[e].b;
    const Coord& back = m_edges[e].a;
    const auto it = std::lower_bound(lo, hi, back, [&](Index o, const Coord& b) {
        return direction_less(at, m_edges[o].b, b);
    });
    return it != lo ? *(it - 1) : *(hi - 1);
}

void PolygonAssembler::trace(Index start)
{
    std::vector<Index>& seq = m_seq;
    seq.clear();
    for (Index h = start; h != k_no && !m_used[h]; h = next(h)) {
        m_used[h] = true;
        const Index v = m_vertex_of_start[h];
        if (m_pos[v] != k_no) { // the trace came back to v: cut the loop that closes there
            const Index k = m_pos[v];
            emit(k);
            for (std::size_t q = k; q < seq.size(); ++q) {
                m_pos[m_vertex_of_start[seq[q]]] = k_no;
            }
            seq.resize(k);
        }
        m_pos[v] = static_cast<Index>(seq.size());
        seq.push_back(h);
    }
    emit(0);
    for (Index h : seq) {
        m_pos[m_vertex_of_start[h]] = k_no;
    }
}

// A simple loop's orientation is the turn at its lexicographically smallest vertex (never
// collinear there: both neighbours lie on one side of a vertical line through it).
void PolygonAssembler::emit(std::size_t from)
{
    const std::vector<Index>& seq = m_seq;
    if (seq.size() < from + 3) {
        return;
    }
    Loop loop;
    loop.pts.reserve(seq.size() - from + 1); // room for the closing point close_and_sort() adds
    for (std::size_t q = from; q < seq.size(); ++q) {
        loop.pts.push_back(m_edges[seq[q]].a);
    }
    const auto low = std::min_element(loop.pts.begin(), loop.pts.end(), xy_less);
    std::rotate(loop.pts.begin(), low, loop.pts.end());
    const int turn = orientation(loop.pts.back(), loop.pts[0], loop.pts[1]);
    if (turn == 0) {
        return;
    }
    loop.shell = turn > 0;
    loop.xmin = loop.xmax = loop.pts[0].x;
    loop.ymin = loop.ymax = loop.pts[0].y;
    for (const Coord& c : loop.pts) {
        loop.xmin = std::min(loop.xmin, c.x);
        loop.xmax = std::max(loop.xmax, c.x);
        loop.ymin = std::min(loop.ymin, c.y);
        loop.ymax = std::max(loop.ymax, c.y);
    }
    m_loops.push_back(std::move(loop));
}

const RingIndex& PolygonAssembler::index_of(std::size_t shell)
{
    if (!m_index[shell]) {
        m_index[shell] = std::make_unique<RingIndex>(m_loops[shell]);
    }
    return *m_index[shell];
}

// Does the shell hold the loop? Loops of a planar subdivision do not cross, so any vertex of the
// loop that is not a vertex of the shell decides; a loop whose every vertex lies on the shell is
// decided by the direction of its first edge at the shell's vertex.
bool PolygonAssembler::inside(std::size_t shell, const Loop& loop)
{
    const RingIndex& index = index_of(shell);
    for (const Coord& p : loop.pts) {
        if (!index.has_vertex(p)) {
            return index.locate(p) > 0;
        }
    }
    const std::vector<Coord>& s = m_loops[shell].pts;
    const auto at = std::find_if(s.begin(), s.end(), [&](const Coord& c) { return same_xy(c, loop.pts[0]); });
    const std::size_t k = static_cast<std::size_t>(at - s.begin());
    const Coord& prev = s[(k + s.size() - 1) % s.size()];
    const Coord& next = s[(k + 1) % s.size()];
    return in_interior_sector(prev, s[k], next, loop.pts[1]);
}

// The innermost shell holding the hole: shells of one feature are nested or apart, so of two
// that hold it the inner one lies in the outer one.
std::size_t PolygonAssembler::holder_of(const Loop& hole)
{
    std::vector<std::size_t> candidates;
    for (std::size_t s = 0; s < m_loops.size(); ++s) {
        if (m_loops[s].shell && box_contains(m_loops[s], hole)) {
            candidates.push_back(s);
        }
    }
    if (candidates.size() <= 1) {
        return candidates.empty() ? k_none : candidates[0];
    }
    std::size_t best = k_none;
    for (std::size_t s : candidates) {
        if (!inside(s, hole)) {
            continue;
        }
        if (best == k_none || inside(best, m_loops[s])) {
            best = s;
        }
    }
    return best;
}

Geometry PolygonAssembler::run(std::vector<Polygon> finished)
{
    Geometry g;
    g.has_z = m_has_z;
    index_vertices();
    for (Index e = 0; e < m_edges.size(); ++e) {
        if (!m_used[e]) {
            trace(e);
        }
    }
    // Each hole's shell first (the tests read the shells' points), then the loops' points moved
    // into the rings (reserved with room for the closing point).
    m_index.resize(m_loops.size());
    std::vector<std::size_t> holder(m_loops.size(), k_none);
    for (std::size_t k = 0; k < m_loops.size(); ++k) {
        if (!m_loops[k].shell) {
            holder[k] = holder_of(m_loops[k]);
        }
    }
    m_index.clear(); // they point into the shells' points
    std::vector<std::size_t> polygon_of(m_loops.size(), k_none);
    for (std::size_t k = 0; k < m_loops.size(); ++k) {
        if (m_loops[k].shell) {
            polygon_of[k] = g.polygons.size();
            // Moved in: Polygon{{...}} would copy it through an initializer_list, at its size.
            g.polygons.emplace_back().rings.push_back(std::move(m_loops[k].pts));
        }
    }
    for (std::size_t k = 0; k < m_loops.size(); ++k) {
        if (holder[k] != k_none) {
            g.polygons[polygon_of[holder[k]]].rings.push_back(std::move(m_loops[k].pts));
        }
    }
    detail::close_and_sort(g);
    if (!finished.empty()) {
        g.polygons.insert(g.polygons.end(), std::make_move_iterator(finished.begin()), std::make_move_iterator(finished.end()));
        std::sort(g.polygons.begin(), g.polygons.end(), detail::polygon_less);
    }
    g.type = g.polygons.empty() ? Geometry::Type::Empty
           : g.polygons.size() == 1 ? Geometry::Type::Polygon : Geometry::Type::MultiPolygon;
    return g;
}

// A finished polygon that shares a vertex (x and y) with an edge or with another finished
// polygon is not a component of its own: its ring edges go back to `edges`, to be traced with
// the rest. Finished polygons that stay share no vertex with anything else, so tracing them
// again would give them back unchanged (their rings are loops of their own, and no traced
// loop lies between one of their holes and their shell: the feature's parts do not overlap).
void take_back_touching(std::vector<DirectedEdge>& edges, std::vector<Polygon>& finished)
{
    struct At {
        double x, y;
        std::uint32_t polygon;
    };
    std::vector<At> at;
    for (std::size_t k = 0; k < finished.size(); ++k) {
        for (const Path& r : finished[k].rings) {
            for (std::size_t i = 0; i + 1 < r.size(); ++i) {
                at.push_back(At{r[i].x, r[i].y, static_cast<std::uint32_t>(k)});
            }
        }
    }
    const auto xy = [](const At& a, const At& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
    std::sort(at.begin(), at.end(), [&](const At& a, const At& b) { return xy(a, b) || (!xy(b, a) && a.polygon < b.polygon); });
    std::vector<bool> back(finished.size(), false);
    for (std::size_t i = 0, j = 0; i < at.size(); i = j) {
        for (j = i + 1; j < at.size() && !xy(at[i], at[j]); ++j) {
        }
        if (at[i].polygon != at[j - 1].polygon) {
            for (std::size_t q = i; q < j; ++q) {
                back[at[q].polygon] = true;
            }
        }
    }
    const auto touch = [&](const Coord& c) {
        const At key{c.x, c.y, 0};
        for (auto it = std::lower_bound(at.begin(), at.end(), key, xy); it != at.end() && !xy(key, *it); ++it) {
            back[it->polygon] = true;
        }
    };
    for (const DirectedEdge& e : edges) {
        touch(e.a);
        touch(e.b);
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < finished.size(); ++k) {
        if (!back[k]) {
            if (kept != k) {
                finished[kept] = std::move(finished[k]);
            }
            ++kept;
            continue;
        }
        append_ring_edges(finished[k], edges);
    }
    finished.resize(kept);
}

} // namespace

void append_ring_edges(const Polygon& polygon, std::vector<DirectedEdge>& out)
{
    for (const Path& r : polygon.rings) {
        for (std::size_t i = 0; i + 1 < r.size(); ++i) {
            out.push_back(DirectedEdge{r[i], r[i + 1]});
        }
    }
}

Geometry assemble_polygons(std::vector<DirectedEdge> edges, bool has_z, std::vector<Polygon> finished)
{
    if (!finished.empty()) {
        take_back_touching(edges, finished);
    }
    return PolygonAssembler(std::move(edges), has_z).run(std::move(finished));
}

} // namespace trisnap
