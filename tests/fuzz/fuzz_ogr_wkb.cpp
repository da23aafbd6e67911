// Fuzz target: arbitrary bytes as WKB -> OGRGeometry -> from_ogr (src/io/ogr_geometry). What
// from_ogr accepts for snapping goes back through to_ogr and from_ogr again and must come back
// with the same type, structure and coordinates (Z too); count_vertices must not crash on
// anything GDAL parsed. A mismatch aborts, so libFuzzer keeps the input.
#include "io/ogr_geometry.hpp"

#include <ogr_geometry.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace {

using trisnap::Coord;
using trisnap::Geometry;
using trisnap::Path;

[[noreturn]] void fail(const char* what)
{
    std::fprintf(stderr, "fuzz_ogr_wkb: %s\n", what);
    std::abort();
}

bool same_z(double a, double b)
{
    return (std::isnan(a) && std::isnan(b)) || a == b;
}

bool same_path(const Path& a, const Path& b, bool has_z)
{
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        // to_ogr writes 0 for a vertex without Z in a 3D geometry.
        const double za = std::isnan(a[i].z) ? 0.0 : a[i].z;
        if (!(a[i] == b[i]) || (has_z && !same_z(za, b[i].z))) {
            return false;
        }
    }
    return true;
}

bool same_geometry(const Geometry& a, const Geometry& b)
{
    if (a.has_z != b.has_z || a.polygons.size() != b.polygons.size() || a.lines.size() != b.lines.size()) {
        return false;
    }
    for (std::size_t p = 0; p < a.polygons.size(); ++p) {
        const auto& ra = a.polygons[p].rings;
        const auto& rb = b.polygons[p].rings;
        if (ra.size() != rb.size()) {
            return false;
        }
        for (std::size_t r = 0; r < ra.size(); ++r) {
            if (!same_path(ra[r], rb[r], a.has_z)) {
                return false;
            }
        }
    }
    for (std::size_t l = 0; l < a.lines.size(); ++l) {
        if (!same_path(a.lines[l], b.lines[l], a.has_z)) {
            return false;
        }
    }
    return true;
}

void check_round_trip(const Geometry& engine, OGRwkbGeometryType like)
{
    std::unique_ptr<OGRGeometry> back(trisnap::to_ogr(engine, like));
    if (!back) {
        if (!engine.empty()) {
            fail("to_ogr returned null for a non-empty geometry");
        }
        return;
    }
    Geometry again;
    if (trisnap::from_ogr(back.get(), again) != trisnap::GeometryVerdict::snap) {
        // An engine geometry whose parts are all empty reads back as an empty OGR geometry.
        if (!back->IsEmpty()) {
            fail("to_ogr output is not accepted by from_ogr");
        }
        return;
    }
    if (!same_geometry(engine, again)) {
        fail("from_ogr(to_ogr(g)) differs from g");
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    OGRGeometry* raw = nullptr;
    if (OGRGeometryFactory::createFromWkb(data, nullptr, &raw, size) != OGRERR_NONE || !raw) {
        return 0;
    }
    std::unique_ptr<OGRGeometry> source(raw);
    (void)trisnap::count_vertices(source.get());
    Geometry engine;
    if (trisnap::from_ogr(source.get(), engine) != trisnap::GeometryVerdict::snap) {
        return 0;
    }
    check_round_trip(engine, wkbFlatten(source->getGeometryType()));
    return 0;
}
