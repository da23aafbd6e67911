#pragma once
// What the polygon and line assemblers share: the exact order and identity of edges and points,
// and the canonical closing and ordering of output rings and parts.
#include "core/assemble.hpp"
#include "core/predicates.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <tuple>

namespace trisnap::detail {

inline bool same_xy(const Coord& a, const Coord& b) { return a.x == b.x && a.y == b.y; }

inline auto edge_key(const DirectedEdge& e)
{
    return std::make_tuple(e.a.x, e.a.y, e.b.x, e.b.y, std::bit_cast<std::uint64_t>(e.a.z),
                           std::bit_cast<std::uint64_t>(e.b.z));
}

/// Edges by start point, end point, then the bits of their z values: a total, exact order.
struct EdgeKeyLess {
    bool operator()(const DirectedEdge& l, const DirectedEdge& r) const { return edge_key(l) < edge_key(r); }
};

inline bool edge_key_equal(const DirectedEdge& l, const DirectedEdge& r) { return edge_key(l) == edge_key(r); }

/// Open rings (starting at their smallest vertex) closed; holes and parts sorted by first vertex.
inline void close_and_sort(Geometry& g)
{
    for (Polygon& p : g.polygons) {
        for (Path& ring : p.rings) {
            ring.push_back(ring.front());
        }
        std::sort(p.rings.begin() + 1, p.rings.end(), [](const Path& a, const Path& b) { return xy_less(a[0], b[0]); });
    }
    std::sort(g.polygons.begin(), g.polygons.end(),
              [](const Polygon& a, const Polygon& b) { return xy_less(a.rings[0][0], b.rings[0][0]); });
}

} // namespace trisnap::detail
