#pragma once
// Directed output edges of one feature, as a tile produced them, compared exactly (x, y and the
// bits of z): two tiles agree on a seam when they produced the very same edges there.
#include "core/geometry.hpp"

#include <cstdint>
#include <cstring>
#include <tuple>
#include <vector>

namespace trisnap::stitch {

inline std::uint64_t bits(double v)
{
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

struct Edge {
    std::uint32_t feature = 0; ///< index of the cleaned feature
    Coord a, b;
    double mx() const { return 0.5 * (a.x + b.x); }
    double my() const { return 0.5 * (a.y + b.y); }
    auto key() const { return std::make_tuple(feature, a.x, a.y, b.x, b.y, bits(a.z), bits(b.z)); }
    friend bool operator<(const Edge& l, const Edge& r) { return l.key() < r.key(); }
    friend bool operator==(const Edge& l, const Edge& r) { return l.key() == r.key(); }
};

/// Every directed edge of a geometry (rings as output: shells counter-clockwise, holes clockwise).
inline void edges_of(const Geometry& g, std::uint32_t feature, std::vector<Edge>& out)
{
    for (const Polygon& p : g.polygons)
        for (const Path& r : p.rings)
            for (std::size_t i = 0; i + 1 < r.size(); ++i) out.push_back(Edge{feature, r[i], r[i + 1]});
    for (const Path& l : g.lines)
        for (std::size_t i = 0; i + 1 < l.size(); ++i) out.push_back(Edge{feature, l[i], l[i + 1]});
}

} // namespace trisnap::stitch
