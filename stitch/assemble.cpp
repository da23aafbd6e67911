#include "stitch/assemble.hpp"

#include "tiling/tile_input.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace trisnap::stitch {
namespace {

bool coord_less(const Coord& a, const Coord& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; }

// Half-plane then cross product: a total order of directions by angle in [0, 2pi).
bool angle_less(double ax, double ay, double bx, double by)
{
    const bool ha = ay < 0 || (ay == 0 && ax < 0), hb = by < 0 || (by == 0 && bx < 0);
    if (ha != hb) return !ha;
    return ax * by - ay * bx > 0;
}

double signed_area(const std::vector<Coord>& ring)
{
    double a = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const Coord &p = ring[i], &q = ring[(i + 1) % ring.size()];
        a += p.x * q.y - q.x * p.y;
    }
    return 0.5 * a;
}

Path close_canonical(std::vector<Coord> ring)
{
    const auto first = std::min_element(ring.begin(), ring.end(), coord_less);
    std::rotate(ring.begin(), first, ring.end());
    ring.push_back(ring.front());
    return ring;
}

struct Loop {
    std::vector<Coord> pts;
    double area = 0;
    double xmin = 0, ymin = 0, xmax = 0, ymax = 0;
};

} // namespace

void canonicalise(Geometry& g)
{
    for (Polygon& p : g.polygons)
        std::sort(p.rings.begin() + 1, p.rings.end(), [](const Path& a, const Path& b) { return coord_less(a[0], b[0]); });
    std::sort(g.polygons.begin(), g.polygons.end(),
              [](const Polygon& a, const Polygon& b) { return coord_less(a.rings[0][0], b.rings[0][0]); });
}

Geometry assemble_polygons(std::vector<Edge> edges, bool has_z)
{
    Geometry g;
    g.has_z = has_z;
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    // Out-edges of each vertex by angle; edges are sorted by start point already.
    std::vector<std::size_t> order(edges.size());
    std::iota(order.begin(), order.end(), 0);
    auto dir_less = [&](std::size_t i, std::size_t j) {
        const Edge &a = edges[i], &b = edges[j];
        if (a.a.x != b.a.x || a.a.y != b.a.y) return coord_less(a.a, b.a);
        return angle_less(a.b.x - a.a.x, a.b.y - a.a.y, b.b.x - b.a.x, b.b.y - b.a.y);
    };
    std::sort(order.begin(), order.end(), dir_less);
    // Range of out-edges (positions in `order`) of the vertex at a point.
    auto range_of = [&](const Coord& v) {
        auto lo = std::lower_bound(order.begin(), order.end(), v, [&](std::size_t k, const Coord& p) { return coord_less(edges[k].a, p); });
        auto hi = std::upper_bound(lo, order.end(), v, [&](const Coord& p, std::size_t k) { return coord_less(p, edges[k].a); });
        return std::make_pair(lo, hi);
    };
    // The edge leaving the end of e within the same sector: the first out-edge clockwise from
    // the direction back along e.
    auto next = [&](std::size_t e) -> std::size_t {
        const Coord& v = edges[e].b;
        auto [lo, hi] = range_of(v);
        if (lo == hi) return edges.size();
        const double bx = edges[e].a.x - v.x, by = edges[e].a.y - v.y;
        // out-edges sorted counter-clockwise; want the largest angle strictly below `back`,
        // else wrap to the largest overall.
        std::size_t best = edges.size();
        for (auto it = lo; it != hi; ++it) {
            const Edge& o = edges[*it];
            if (angle_less(o.b.x - v.x, o.b.y - v.y, bx, by)) best = *it;
        }
        return best != edges.size() ? best : *(hi - 1);
    };
    std::vector<bool> used(edges.size(), false);
    std::vector<Loop> loops;
    auto emit = [&](std::vector<Coord> pts) {
        Loop l;
        l.area = signed_area(pts);
        l.xmin = l.xmax = pts[0].x, l.ymin = l.ymax = pts[0].y;
        for (const Coord& c : pts) l.xmin = std::min(l.xmin, c.x), l.xmax = std::max(l.xmax, c.x), l.ymin = std::min(l.ymin, c.y), l.ymax = std::max(l.ymax, c.y);
        l.pts = std::move(pts);
        loops.push_back(std::move(l));
    };
    for (std::size_t start = 0; start < edges.size(); ++start) {
        if (used[start]) continue;
        std::vector<Coord> seq;
        std::map<std::pair<double, double>, std::size_t> pos;
        for (std::size_t h = start; h < edges.size() && !used[h]; h = next(h)) {
            used[h] = true;
            const Coord& v = edges[h].a;
            if (auto it = pos.find({v.x, v.y}); it != pos.end()) { // cut the loop that closes at v
                const std::size_t k = it->second;
                std::vector<Coord> loop(seq.begin() + static_cast<std::ptrdiff_t>(k), seq.end());
                for (std::size_t q = k; q < seq.size(); ++q) pos.erase({seq[q].x, seq[q].y});
                seq.resize(k);
                emit(std::move(loop));
            }
            pos[{v.x, v.y}] = seq.size();
            seq.push_back(v);
        }
        if (seq.size() >= 3) emit(std::move(seq));
    }
    // Shells, then each hole into the innermost shell that holds it.
    std::vector<std::size_t> shells;
    for (std::size_t k = 0; k < loops.size(); ++k)
        if (loops[k].area > 0) shells.push_back(k);
    std::vector<std::size_t> polygon_of(loops.size(), 0);
    for (std::size_t s : shells) {
        polygon_of[s] = g.polygons.size();
        g.polygons.push_back(Polygon{{close_canonical(loops[s].pts)}});
    }
    for (const Loop& hole : loops) {
        if (hole.area >= 0) continue;
        std::size_t best = loops.size();
        std::vector<std::size_t> candidates;
        for (std::size_t s : shells) {
            const Loop& sh = loops[s];
            if (sh.xmin <= hole.xmin && hole.xmax <= sh.xmax && sh.ymin <= hole.ymin && hole.ymax <= sh.ymax) candidates.push_back(s);
        }
        if (candidates.size() == 1) {
            best = candidates[0];
        } else {
            for (std::size_t s : candidates) {
                const Loop& sh = loops[s];
                // A hole vertex that is not a vertex of the shell lies strictly inside or outside
                // it (vertices keep >= t/2 from edges they are not on).
                std::vector<Coord> sorted = sh.pts;
                std::sort(sorted.begin(), sorted.end(), coord_less);
                bool decided = false, inside = false;
                for (const Coord& p : hole.pts) {
                    if (std::binary_search(sorted.begin(), sorted.end(), p, coord_less)) continue;
                    inside = tiling::point_in_ring(sh.pts, p.x, p.y), decided = true;
                    break;
                }
                if (!decided || !inside) continue;
                if (best == loops.size() || sh.area < loops[best].area) best = s;
            }
        }
        if (best != loops.size()) g.polygons[polygon_of[best]].rings.push_back(close_canonical(hole.pts));
    }
    canonicalise(g);
    g.type = g.polygons.empty() ? Geometry::Type::Empty
           : g.polygons.size() == 1 ? Geometry::Type::Polygon : Geometry::Type::MultiPolygon;
    return g;
}

Geometry assemble_lines(std::vector<Edge> edges, const std::vector<Coord>& part_starts, bool has_z)
{
    Geometry g;
    g.has_z = has_z;
    std::sort(edges.begin(), edges.end());
    std::map<std::pair<double, double>, int> balance;
    for (const Edge& e : edges) ++balance[{e.a.x, e.a.y}], --balance[{e.b.x, e.b.y}];
    std::vector<bool> used(edges.size(), false);
    auto take = [&](const Coord& v) -> std::size_t {
        auto lo = std::lower_bound(edges.begin(), edges.end(), v, [](const Edge& e, const Coord& p) { return coord_less(e.a, p); });
        for (auto it = lo; it != edges.end() && it->a.x == v.x && it->a.y == v.y; ++it)
            if (!used[static_cast<std::size_t>(it - edges.begin())]) return static_cast<std::size_t>(it - edges.begin());
        return edges.size();
    };
    auto trail = [&](std::size_t k) {
        Path path{edges[k].a};
        for (; k < edges.size(); k = take(path.back())) {
            used[k] = true;
            path.push_back(edges[k].b);
        }
        return path;
    };
    auto walk = [&](std::size_t k) { g.lines.push_back(trail(k)); };
    // A closed trail that starts on a line already traced is a loop the walk stepped past
    // (a line through one vertex twice): splice it in there rather than make a part of it.
    auto splice = [&](Path loop) {
        if (loop.front() == loop.back())
            for (Path& line : g.lines)
                for (std::size_t i = 0; i < line.size(); ++i)
                    if (line[i] == loop.front()) {
                        line.insert(line.begin() + static_cast<std::ptrdiff_t>(i) + 1, loop.begin() + 1, loop.end());
                        return;
                    }
        g.lines.push_back(std::move(loop));
    };
    for (const Coord& s : part_starts)
        if (std::size_t k = take(s); k < edges.size()) walk(k);
    for (std::size_t k = 0; k < edges.size(); ++k)
        if (!used[k] && balance[{edges[k].a.x, edges[k].a.y}] > 0) walk(k);
    for (std::size_t k = 0; k < edges.size(); ++k)
        if (!used[k]) splice(trail(k));
    g.type = g.lines.empty() ? Geometry::Type::Empty
           : g.lines.size() == 1 ? Geometry::Type::LineString : Geometry::Type::MultiLineString;
    return g;
}

} // namespace trisnap::stitch
