#include "io/ogr_geometry.hpp"

#include <cmath>
#include <limits>
#include <memory>

namespace trisnap {
namespace {

/// Z is kept only when finite: the engine averages the z of merged vertices and interpolates
/// along edges, so one infinite z would spread to every neighbour that shares the vertex. A NaN
/// z means "no z" to the engine, which then takes the z of what the vertex merges with.
double checked_z(double z, ReadNotes& notes)
{
    if (std::isfinite(z)) {
        return z;
    }
    ++notes.non_finite_z;
    return std::numeric_limits<double>::quiet_NaN();
}

bool read_path(const OGRSimpleCurve& curve, Path& out, ReadNotes& notes)
{
    const int n = curve.getNumPoints();
    out.reserve(static_cast<std::size_t>(n));
    const bool has_z = curve.Is3D();
    for (int i = 0; i < n; ++i) {
        Coord c{curve.getX(i), curve.getY(i)};
        if (has_z) {
            c.z = checked_z(curve.getZ(i), notes);
        }
        if (!std::isfinite(c.x) || !std::isfinite(c.y)) {
            return false;
        }
        out.push_back(c);
    }
    return true;
}

bool read_polygon(const OGRPolygon& polygon, Polygon& out, ReadNotes& notes)
{
    for (const OGRLinearRing* ring : polygon) {
        out.rings.emplace_back();
        if (!read_path(*ring, out.rings.back(), notes)) {
            return false;
        }
    }
    return true;
}

bool read_linear(const OGRGeometry& g, Geometry& out, ReadNotes& notes)
{
    switch (wkbFlatten(g.getGeometryType())) {
    case wkbPolygon:
        out.polygons.emplace_back();
        return read_polygon(*g.toPolygon(), out.polygons.back(), notes);
    case wkbMultiPolygon:
        for (const OGRPolygon* p : *g.toMultiPolygon()) {
            out.polygons.emplace_back();
            if (!read_polygon(*p, out.polygons.back(), notes)) {
                return false;
            }
        }
        return true;
    case wkbLineString:
        out.lines.emplace_back();
        return read_path(*g.toLineString(), out.lines.back(), notes);
    default: // wkbMultiLineString, checked by the caller
        for (const OGRLineString* l : *g.toMultiLineString()) {
            out.lines.emplace_back();
            if (!read_path(*l, out.lines.back(), notes)) {
                return false;
            }
        }
        return true;
    }
}

Geometry::Type engine_type(OGRwkbGeometryType flat)
{
    switch (flat) {
    case wkbPolygon: return Geometry::Type::Polygon;
    case wkbMultiPolygon: return Geometry::Type::MultiPolygon;
    case wkbLineString: return Geometry::Type::LineString;
    case wkbMultiLineString: return Geometry::Type::MultiLineString;
    default: return Geometry::Type::Empty;
    }
}

OGRLineString* make_curve(const Path& path, bool has_z, OGRLineString* curve)
{
    curve->setNumPoints(static_cast<int>(path.size()), FALSE);
    for (std::size_t i = 0; i < path.size(); ++i) {
        const Coord& c = path[i];
        if (has_z) curve->setPoint(static_cast<int>(i), c.x, c.y, std::isnan(c.z) ? 0.0 : c.z);
        else curve->setPoint(static_cast<int>(i), c.x, c.y);
    }
    return curve;
}

OGRPolygon* make_polygon(const Polygon& polygon, bool has_z)
{
    auto* out = new OGRPolygon();
    for (const Path& ring : polygon.rings)
        out->addRingDirectly(static_cast<OGRLinearRing*>(make_curve(ring, has_z, new OGRLinearRing())));
    return out;
}

OGRGeometry* make_polygonal(const Geometry& g, bool multi)
{
    if (!multi) return make_polygon(g.polygons[0], g.has_z);
    auto* out = new OGRMultiPolygon();
    for (const Polygon& p : g.polygons) out->addGeometryDirectly(make_polygon(p, g.has_z));
    return out;
}

OGRGeometry* make_lineal(const Geometry& g, bool multi)
{
    if (!multi) return make_curve(g.lines[0], g.has_z, new OGRLineString());
    auto* out = new OGRMultiLineString();
    for (const Path& l : g.lines) out->addGeometryDirectly(make_curve(l, g.has_z, new OGRLineString()));
    return out;
}

} // namespace

GeometryVerdict from_ogr(const OGRGeometry* source, Geometry& out)
{
    ReadNotes ignored;
    return from_ogr(source, out, ignored);
}

GeometryVerdict from_ogr(const OGRGeometry* source, Geometry& out, ReadNotes& notes)
{
    if (!source || source->IsEmpty()) return GeometryVerdict::empty;
    const OGRwkbGeometryType type = wkbFlatten(source->getGeometryType());
    if (type == wkbPoint || type == wkbMultiPoint) return GeometryVerdict::pass_through;
    std::unique_ptr<OGRGeometry> linear;
    if (OGR_GT_IsNonLinear(type)) linear.reset(source->getLinearGeometry());
    const OGRGeometry& g = linear ? *linear : *source;
    out = Geometry{};
    out.type = engine_type(wkbFlatten(g.getGeometryType()));
    if (out.type == Geometry::Type::Empty) return GeometryVerdict::unsupported;
    out.has_z = g.Is3D();
    if (!read_linear(g, out, notes)) return GeometryVerdict::non_finite;
    return GeometryVerdict::snap;
}

OGRGeometry* to_ogr(const Geometry& geometry, OGRwkbGeometryType like)
{
    if (geometry.empty()) return nullptr;
    const bool multi = written_multi(geometry, like);
    if (!geometry.polygons.empty()) return make_polygonal(geometry, multi);
    return make_lineal(geometry, multi);
}

bool written_multi(const Geometry& geometry, OGRwkbGeometryType like)
{
    const bool multi_input = like == wkbMultiPolygon || like == wkbMultiLineString ||
                             like == wkbMultiSurface || like == wkbMultiCurve;
    const std::size_t parts = geometry.polygons.empty() ? geometry.lines.size() : geometry.polygons.size();
    return multi_input || parts != 1;
}

std::size_t count_vertices(const OGRGeometry* geometry)
{
    if (!geometry) return 0;
    const OGRwkbGeometryType type = wkbFlatten(geometry->getGeometryType());
    if (OGR_GT_IsSubClassOf(type, wkbCurve)) {
        if (type == wkbCompoundCurve) {
            std::size_t n = 0;
            for (const OGRCurve* c : *geometry->toCompoundCurve()) n += count_vertices(c);
            return n;
        }
        return static_cast<std::size_t>(geometry->toSimpleCurve()->getNumPoints());
    }
    if (OGR_GT_IsSubClassOf(type, wkbCurvePolygon)) {
        std::size_t n = 0;
        for (const OGRCurve* ring : *geometry->toCurvePolygon()) n += count_vertices(ring);
        return n;
    }
    if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
        std::size_t n = 0;
        for (const OGRGeometry* part : *geometry->toGeometryCollection()) n += count_vertices(part);
        return n;
    }
    if (type == wkbPolyhedralSurface || type == wkbTIN) {
        std::size_t n = 0;
        for (const OGRPolygon* part : *geometry->toPolyhedralSurface()) n += count_vertices(part);
        return n;
    }
    return type == wkbPoint ? 1 : 0;
}

} // namespace trisnap
