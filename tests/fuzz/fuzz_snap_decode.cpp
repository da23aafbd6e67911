#include "fuzz_snap_decode.hpp"

#include "core/wkt.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace trisnap::fuzz {

std::uint8_t ByteReader::byte()
{
    if (m_pos >= m_size) {
        return 0;
    }
    return m_data[m_pos++];
}

std::uint16_t ByteReader::u16()
{
    const std::uint16_t lo = byte();
    const std::uint16_t hi = byte();
    return static_cast<std::uint16_t>(lo | (hi << 8));
}

double ByteReader::raw_double()
{
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) {
        bits |= std::uint64_t{byte()} << (8 * i);
    }
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

namespace {

constexpr std::size_t k_max_features = 6;
constexpr std::size_t k_max_parts = 3;
constexpr std::size_t k_max_points = 12;

/// (1 + m/256) * 2^e with e a signed byte: 2^-128 .. 2^128, the range where snapping is usual.
double scaled(ByteReader& in)
{
    const double mantissa = 1.0 + in.byte() / 256.0;
    const int exponent = static_cast<std::int8_t>(in.byte());
    return std::ldexp(mantissa, exponent);
}

double fraction(ByteReader& in) { return in.byte() / 255.0; }

void decode_options(ByteReader& in, SnapOptions& o)
{
    const std::uint8_t mode = in.byte();
    o.tolerance = (mode & 1) ? in.raw_double() : scaled(in);
    const double edge[] = {0.5, 1.0, 0.25, fraction(in)};
    o.edge_separation = edge[(mode >> 1) & 3];
    const double sliver[] = {0.5, 0.0, 1.0, fraction(in)};
    o.sliver_factor = sliver[(mode >> 3) & 3];
    const double grid[] = {0.0, 0.0, o.tolerance / 4, o.tolerance / 16};
    o.grid = grid[(mode >> 5) & 3];
    o.max_operations = (mode & 0x80) ? in.byte() : 0;
}

/// Coordinates on a grid of `unit` around `origin` (16-bit steps), or raw doubles.
struct CoordDecoder {
    bool raw = false;
    double unit = 1.0;
    double ox = 0.0;
    double oy = 0.0;

    Coord next(ByteReader& in) const
    {
        if (raw) {
            const double x = in.raw_double();
            return Coord{x, in.raw_double()};
        }
        const double x = ox + unit * static_cast<std::int16_t>(in.u16());
        return Coord{x, oy + unit * static_cast<std::int16_t>(in.u16())};
    }
};

CoordDecoder decode_coords(ByteReader& in, double tolerance)
{
    const std::uint8_t mode = in.byte();
    CoordDecoder d;
    d.raw = (mode & 3) == 3;
    // Grid steps from t/64 to 4t: most vertices are a few t apart, so every snap case happens.
    d.unit = tolerance * std::ldexp(1.0, static_cast<int>(mode >> 2 & 7) - 6);
    if (mode & 0x20) {
        d.ox = in.raw_double();
        d.oy = in.raw_double();
    }
    return d;
}

Path decode_path(ByteReader& in, const CoordDecoder& coords, bool ring)
{
    const std::uint8_t head = in.byte();
    const std::size_t n = head % (k_max_points + 1);
    Path path;
    for (std::size_t i = 0; i < n; ++i) {
        path.push_back(coords.next(in));
    }
    // Most rings are closed (valid input); bit 7 leaves one open for the engine to repair.
    if (ring && !path.empty() && !(head & 0x80)) {
        path.push_back(path.front());
    }
    return path;
}

Feature decode_feature(ByteReader& in, const CoordDecoder& coords, std::int64_t id)
{
    const std::uint8_t head = in.byte();
    Feature f;
    f.id = id;
    const std::size_t parts = 1 + (head >> 2) % k_max_parts;
    const std::size_t rings = 1 + (head >> 4) % k_max_parts;
    switch (head & 3) {
    case 0:
        f.geometry.type = Geometry::Type::Polygon;
        break;
    case 1:
        f.geometry.type = Geometry::Type::MultiPolygon;
        break;
    case 2:
        f.geometry.type = Geometry::Type::LineString;
        break;
    default:
        f.geometry.type = Geometry::Type::MultiLineString;
        break;
    }
    const bool multi = (head & 1) != 0;
    if (f.geometry.is_polygonal()) {
        for (std::size_t p = 0; p < (multi ? parts : 1); ++p) {
            Polygon polygon;
            for (std::size_t r = 0; r < rings; ++r) {
                polygon.rings.push_back(decode_path(in, coords, true));
            }
            f.geometry.polygons.push_back(std::move(polygon));
        }
    } else {
        for (std::size_t l = 0; l < (multi ? parts : 1); ++l) {
            f.geometry.lines.push_back(decode_path(in, coords, false));
        }
    }
    return f;
}

std::string hex(double v)
{
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%a", v);
    return buffer;
}

} // namespace

SnapProblem decode_snap_problem(const std::uint8_t* data, std::size_t size)
{
    ByteReader in(data, size);
    SnapProblem problem;
    decode_options(in, problem.options);
    const CoordDecoder coords = decode_coords(in, problem.options.tolerance);
    const std::size_t n = 1 + in.byte() % k_max_features;
    for (std::size_t i = 0; i < n && !in.done(); ++i) {
        problem.features.push_back(decode_feature(in, coords, static_cast<std::int64_t>(i + 1)));
    }
    return problem;
}

std::string describe(const SnapProblem& problem)
{
    const SnapOptions& o = problem.options;
    std::string out = "tolerance " + hex(o.tolerance) + " edge_separation " + hex(o.edge_separation) +
                      " sliver_factor " + hex(o.sliver_factor) + " grid " + hex(o.grid) +
                      " max_operations " + std::to_string(o.max_operations) + "\n";
    for (const Feature& f : problem.features) {
        out += std::to_string(f.id) + ";" + to_wkt(f.geometry) + "\n";
    }
    return out;
}

} // namespace trisnap::fuzz
