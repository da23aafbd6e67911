#include "tiling/records.hpp"

#include <cmath>

namespace trisnap::tiling {
namespace {

constexpr std::size_t k_xy = 2 * sizeof(double);

void put_path(ByteWriter& w, const std::vector<Coord>& path, bool has_z)
{
    w.put<std::uint32_t>(static_cast<std::uint32_t>(path.size()));
    for (const Coord& c : path) {
        w.put(c.x);
        w.put(c.y);
        if (has_z) {
            w.put(c.z);
        }
    }
}

std::vector<Coord> get_path(ByteReader& r, bool has_z)
{
    const std::uint32_t n = r.get_count(has_z ? k_xy + sizeof(double) : k_xy);
    std::vector<Coord> path(n);
    for (Coord& c : path) {
        c.x = r.get<double>();
        c.y = r.get<double>();
        c.z = has_z ? r.get<double>() : std::nan("");
    }
    return path;
}

// A path's first point only (the rest skipped): what the stitch needs of a spooled feature.
std::vector<Coord> get_path_head(ByteReader& r, bool has_z)
{
    const std::size_t bytes = has_z ? k_xy + sizeof(double) : k_xy;
    const std::uint32_t n = r.get_count(bytes);
    std::vector<Coord> path;
    if (n > 0) {
        Coord c;
        c.x = r.get<double>();
        c.y = r.get<double>();
        c.z = has_z ? r.get<double>() : std::nan("");
        path.push_back(c);
        r.skip((n - 1) * bytes);
    }
    return path;
}

} // namespace

// Z is stored only for geometries that have it; without, every z reads back as NaN (as the
// reader and the engine make it).
void put_geometry(ByteWriter& w, const Geometry& g)
{
    w.put<std::uint8_t>(static_cast<std::uint8_t>(g.type));
    w.put<std::uint8_t>(g.has_z ? 1 : 0);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(g.polygons.size()));
    for (const Polygon& p : g.polygons) {
        w.put<std::uint32_t>(static_cast<std::uint32_t>(p.rings.size()));
        for (const Path& ring : p.rings) {
            put_path(w, ring, g.has_z);
        }
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(g.lines.size()));
    for (const Path& line : g.lines) {
        put_path(w, line, g.has_z);
    }
}

Geometry get_geometry(ByteReader& r)
{
    Geometry g;
    const auto type = r.get<std::uint8_t>();
    if (type > static_cast<std::uint8_t>(Geometry::Type::MultiLineString)) {
        throw record_error("damaged work file: unknown geometry type in a record");
    }
    g.type = static_cast<Geometry::Type>(type);
    g.has_z = r.get<std::uint8_t>() != 0;
    g.polygons.resize(r.get_count(sizeof(std::uint32_t)));
    for (Polygon& p : g.polygons) {
        p.rings.resize(r.get_count(sizeof(std::uint32_t)));
        for (Path& ring : p.rings) {
            ring = get_path(r, g.has_z);
        }
    }
    g.lines.resize(r.get_count(sizeof(std::uint32_t)));
    for (Path& line : g.lines) {
        line = get_path(r, g.has_z);
    }
    return g;
}

void put_clean_feature(ByteWriter& w, const detail::CleanFeature& f, bool has_z)
{
    w.put<std::uint64_t>(f.index);
    w.put<std::int64_t>(f.id);
    w.put<std::uint8_t>(static_cast<std::uint8_t>((f.polygonal ? 1 : 0) | (f.rejected ? 2 : 0) | (has_z ? 4 : 0)));
    w.put<std::uint64_t>(f.shells);
    w.put<std::uint64_t>(f.holes);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(f.rings.size()));
    for (const detail::CleanRing& ring : f.rings) {
        w.put<std::uint32_t>(ring.polygon);
        w.put<std::uint8_t>(ring.hole ? 1 : 0);
        put_path(w, ring.points, has_z);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(f.lines.size()));
    for (const auto& line : f.lines) {
        put_path(w, line, has_z);
    }
}

detail::CleanFeature get_clean_feature(ByteReader& r, bool& has_z, bool outline)
{
    const auto path = outline ? get_path_head : get_path;
    detail::CleanFeature f;
    f.index = r.get<std::uint64_t>();
    f.id = r.get<std::int64_t>();
    const auto flags = r.get<std::uint8_t>();
    f.polygonal = (flags & 1) != 0;
    f.rejected = (flags & 2) != 0;
    has_z = (flags & 4) != 0;
    f.shells = r.get<std::uint64_t>();
    f.holes = r.get<std::uint64_t>();
    f.rings.resize(r.get_count(sizeof(std::uint32_t) + 1));
    for (detail::CleanRing& ring : f.rings) {
        ring.polygon = r.get<std::uint32_t>();
        ring.hole = r.get<std::uint8_t>() != 0;
        ring.points = path(r, has_z);
    }
    f.lines.resize(r.get_count(sizeof(std::uint32_t)));
    for (auto& line : f.lines) {
        line = path(r, has_z);
    }
    return f;
}

namespace {

// A path's count and first point copied, the rest skipped; the count written is 1 (or 0).
void put_path_head(ByteWriter& w, ByteReader& r, bool has_z)
{
    const std::size_t bytes = has_z ? k_xy + sizeof(double) : k_xy;
    const std::uint32_t n = r.get_count(bytes);
    w.put<std::uint32_t>(n > 0 ? 1 : 0);
    if (n > 0) {
        for (std::size_t k = 0; k < bytes / sizeof(double); ++k) {
            w.put(r.get<double>());
        }
        r.skip((n - 1) * bytes);
    }
}

} // namespace

void put_clean_outline(ByteWriter& w, ByteReader& r)
{
    w.put(r.get<std::uint64_t>()); // index
    w.put(r.get<std::int64_t>());  // id
    const auto flags = r.get<std::uint8_t>();
    const bool has_z = (flags & 4) != 0;
    w.put(flags);
    w.put(r.get<std::uint64_t>()); // shells
    w.put(r.get<std::uint64_t>()); // holes
    const std::uint32_t rings = r.get_count(sizeof(std::uint32_t) + 1);
    w.put(rings);
    for (std::uint32_t k = 0; k < rings; ++k) {
        w.put(r.get<std::uint32_t>()); // polygon
        w.put(r.get<std::uint8_t>());  // hole
        put_path_head(w, r, has_z);
    }
    const std::uint32_t lines = r.get_count(sizeof(std::uint32_t));
    w.put(lines);
    for (std::uint32_t k = 0; k < lines; ++k) {
        put_path_head(w, r, has_z);
    }
}

void put_tile_feature(ByteWriter& w, const TileFeature& f)
{
    w.put<std::uint64_t>(f.rank);
    w.put<std::int64_t>(f.feature.id);
    w.put<std::uint8_t>(f.intact ? 1 : 0);
    put_geometry(w, f.feature.geometry);
}

TileFeature get_tile_feature(ByteReader& r)
{
    TileFeature f;
    f.rank = r.get<std::uint64_t>();
    f.feature.id = r.get<std::int64_t>();
    f.intact = r.get<std::uint8_t>() != 0;
    f.feature.geometry = get_geometry(r);
    return f;
}

void put_edges(ByteWriter& w, const std::vector<DirectedEdge>& edges, bool has_z)
{
    w.put<std::uint8_t>(has_z ? 1 : 0);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(edges.size()));
    for (const DirectedEdge& e : edges) {
        for (const Coord* c : {&e.a, &e.b}) {
            w.put(c->x);
            w.put(c->y);
            if (has_z) {
                w.put(c->z);
            }
        }
    }
}

std::vector<DirectedEdge> get_edges(ByteReader& r)
{
    const bool has_z = r.get<std::uint8_t>() != 0;
    std::vector<DirectedEdge> edges(r.get_count(2 * (has_z ? k_xy + sizeof(double) : k_xy)));
    for (DirectedEdge& e : edges) {
        for (Coord* c : {&e.a, &e.b}) {
            c->x = r.get<double>();
            c->y = r.get<double>();
            c->z = has_z ? r.get<double>() : std::nan("");
        }
    }
    return edges;
}

void put_problem(ByteWriter& w, const Problem& p)
{
    w.put<std::int64_t>(p.feature_id);
    w.put<std::int32_t>(static_cast<std::int32_t>(p.code));
    w.put_string(p.message);
    w.put(p.x);
    w.put(p.y);
}

Problem get_problem(ByteReader& r)
{
    Problem p;
    p.feature_id = r.get<std::int64_t>();
    p.code = static_cast<ProblemCode>(r.get<std::int32_t>());
    p.message = r.get_string();
    p.x = r.get<double>();
    p.y = r.get<double>();
    return p;
}

} // namespace trisnap::tiling
