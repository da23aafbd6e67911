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

/// Edges by start point, end point, then the bits of their z values: a total, exact order
/// (edge_key's, compared field by field without building the keys: 0.5 % fewer instructions
/// on NE land than comparing the tuples).
struct EdgeKeyLess {
    bool operator()(const DirectedEdge& l, const DirectedEdge& r) const
    {
        if (l.a.x < r.a.x) return true;
        if (r.a.x < l.a.x) return false;
        if (l.a.y < r.a.y) return true;
        if (r.a.y < l.a.y) return false;
        if (l.b.x < r.b.x) return true;
        if (r.b.x < l.b.x) return false;
        if (l.b.y < r.b.y) return true;
        if (r.b.y < l.b.y) return false;
        const auto za = std::bit_cast<std::uint64_t>(l.a.z), zb = std::bit_cast<std::uint64_t>(r.a.z);
        if (za != zb) return za < zb;
        return std::bit_cast<std::uint64_t>(l.b.z) < std::bit_cast<std::uint64_t>(r.b.z);
    }
};

inline bool edge_key_equal(const DirectedEdge& l, const DirectedEdge& r) { return edge_key(l) == edge_key(r); }

/// A total order on rings: point by point (x, then y), a prefix first. Rings start at their
/// smallest vertex, so two rings of one output compare by that vertex unless they share it.
inline bool ring_less(const Path& a, const Path& b)
{
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), xy_less);
}

/// A total order on polygons: ring by ring. Being total, it sorts the same polygons to the
/// same order whatever order they come in (the tiled path adds finished polygons to traced ones).
inline bool polygon_less(const Polygon& a, const Polygon& b)
{
    return std::lexicographical_compare(a.rings.begin(), a.rings.end(), b.rings.begin(), b.rings.end(), ring_less);
}

/// Holes sorted (the shell stays first); then the polygons sorted.
inline void sort_canonical(std::vector<Polygon>& polygons)
{
    for (Polygon& p : polygons) {
        std::sort(p.rings.begin() + 1, p.rings.end(), ring_less);
    }
    std::sort(polygons.begin(), polygons.end(), polygon_less);
}

/// Open rings (starting at their smallest vertex) closed; holes and parts sorted.
inline void close_and_sort(Geometry& g)
{
    for (Polygon& p : g.polygons) {
        for (Path& ring : p.rings) {
            ring.push_back(ring.front()); // the assembler made room for it (emit())
        }
    }
    sort_canonical(g.polygons);
}

} // namespace trisnap::detail
