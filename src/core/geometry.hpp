#pragma once
// Plain geometry types at the boundary of the engine: what callers hand in and get back.
// No CGAL here, so I/O code and tests can use them without pulling in the kernel.
#include <cstdint>
#include <limits>
#include <vector>

namespace trisnap {

/// A 2D or 2.5D coordinate. `z` is NaN when the geometry has no Z.
struct Coord {
    double x = 0.0;
    double y = 0.0;
    double z = std::numeric_limits<double>::quiet_NaN();
    friend bool operator==(const Coord& a, const Coord& b) { return a.x == b.x && a.y == b.y; }
};

/// A linestring, or a ring. Rings are stored closed (first == last), as in WKT and OGR.
using Path = std::vector<Coord>;

/// rings[0] is the shell, the others are holes. Orientation on input is free; on output shells
/// are counter-clockwise and holes clockwise.
struct Polygon {
    std::vector<Path> rings;
};

struct Geometry {
    enum class Type { Empty, Polygon, MultiPolygon, LineString, MultiLineString };
    Type type = Type::Empty;
    std::vector<Polygon> polygons; ///< for Polygon / MultiPolygon
    std::vector<Path> lines;       ///< for LineString / MultiLineString
    bool has_z = false;

    bool empty() const { return polygons.empty() && lines.empty(); }
    bool is_polygonal() const { return type == Type::Polygon || type == Type::MultiPolygon; }
    bool is_lineal() const { return type == Type::LineString || type == Type::MultiLineString; }
};

/// One input feature. `id` identifies it in the output and in problem reports; ids should be
/// unique (the engine orders work by id, so duplicates make the result depend on input order).
struct Feature {
    std::int64_t id = 0;
    Geometry geometry;
};

} // namespace trisnap
