#pragma once
// Bit-for-bit comparisons of work records for the round-trip tests (test_records.cpp,
// test_tile_result.cpp): each returns how many points it compared, so that a test whose input
// was dropped before encoding (and compared nothing) fails.
#include "core/geometry.hpp"
#include "tiling/binary_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace trisnap::test_records {

inline std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

inline const double k_payload_nan = std::bit_cast<double>(0x7ff8dead00000001ull);
inline const double k_negative_nan = std::bit_cast<double>(0xfff0000000000123ull); // signalling, sign set

// Compares two point lists bit for bit (z only when `has_z`; without, z must read back NaN) and
// returns how many points it compared.
inline std::size_t same_points(const std::vector<Coord>& a, const std::vector<Coord>& b, bool has_z)
{
    EXPECT_EQ(a.size(), b.size());
    std::size_t compared = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        EXPECT_EQ(bits(a[i].x), bits(b[i].x)) << "x of point " << i;
        EXPECT_EQ(bits(a[i].y), bits(b[i].y)) << "y of point " << i;
        if (has_z) {
            EXPECT_EQ(bits(a[i].z), bits(b[i].z)) << "z of point " << i;
        } else {
            EXPECT_TRUE(std::isnan(b[i].z)) << "z of point " << i << " without Z";
        }
        ++compared;
    }
    return compared;
}

inline std::size_t same_geometry(const Geometry& a, const Geometry& b)
{
    EXPECT_EQ(a.type, b.type);
    EXPECT_EQ(a.has_z, b.has_z);
    std::size_t compared = 0;
    EXPECT_EQ(a.polygons.size(), b.polygons.size());
    for (std::size_t p = 0; p < std::min(a.polygons.size(), b.polygons.size()); ++p) {
        EXPECT_EQ(a.polygons[p].rings.size(), b.polygons[p].rings.size());
        for (std::size_t r = 0; r < std::min(a.polygons[p].rings.size(), b.polygons[p].rings.size()); ++r) {
            compared += same_points(a.polygons[p].rings[r], b.polygons[p].rings[r], a.has_z);
        }
    }
    EXPECT_EQ(a.lines.size(), b.lines.size());
    for (std::size_t l = 0; l < std::min(a.lines.size(), b.lines.size()); ++l) {
        compared += same_points(a.lines[l], b.lines[l], a.has_z);
    }
    return compared;
}

// Values a double can take that a careless encoding loses: signed zeros, NaN payloads,
// subnormals, extremes, the neighbours of 1.
inline Path awkward_path(double shift)
{
    return {{-0.0, 1e-300, k_payload_nan},
            {std::nextafter(1.0, 2.0) + shift, -0.0, -0.0},
            {3 + shift, std::numeric_limits<double>::denorm_min(), 5e-324},
            {-1.7e308, 4 + shift, k_negative_nan},
            {std::nextafter(1.0, 0.0), 1.7e308, std::numeric_limits<double>::infinity()}};
}

inline Geometry awkward_geometry(bool polygon)
{
    Geometry g;
    g.has_z = true;
    const Path p = awkward_path(0);
    if (polygon) {
        g.type = Geometry::Type::MultiPolygon;
        g.polygons = {Polygon{{p, awkward_path(1)}}, Polygon{{awkward_path(2)}}};
    } else {
        g.type = Geometry::Type::MultiLineString;
        g.lines = {p, Path{{1, 2, 3}, {4, 5, 6}}};
    }
    return g;
}

template <class T, class Put, class Get>
T round_trip(const T& value, Put put, Get get, std::string* encoded = nullptr)
{
    std::string bytes;
    tiling::ByteWriter w(bytes);
    put(w, value);
    tiling::ByteReader r(bytes, "test");
    T back = get(r);
    EXPECT_TRUE(r.done()) << "bytes left after decoding";
    if (encoded) {
        *encoded = bytes;
    }
    return back;
}

} // namespace trisnap::test_records
