#include "layer_loader.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <memory>
#include <stdexcept>

namespace trisnap {
namespace {

Path path_of(const OGRSimpleCurve& curve) {
    Path path;
    path.reserve(static_cast<std::size_t>(curve.getNumPoints()));
    const bool z = curve.Is3D();
    for (int i = 0; i < curve.getNumPoints(); ++i) {
        Coord c{curve.getX(i), curve.getY(i)};
        if (z)
            c.z = curve.getZ(i);
        path.push_back(c);
    }
    return path;
}

Polygon polygon_of(const OGRPolygon& polygon) {
    Polygon out;
    for (const OGRLinearRing* ring : polygon)
        out.rings.push_back(path_of(*ring));
    return out;
}

/// Fills `out` from a linear geometry; false for types the engine does not take.
bool convert(const OGRGeometry& g, Geometry& out) {
    out.has_z = g.Is3D();
    switch (wkbFlatten(g.getGeometryType())) {
    case wkbPolygon:
        out.type = Geometry::Type::Polygon;
        out.polygons.push_back(polygon_of(*g.toPolygon()));
        return true;
    case wkbMultiPolygon:
        out.type = Geometry::Type::MultiPolygon;
        for (const OGRPolygon* p : *g.toMultiPolygon())
            out.polygons.push_back(polygon_of(*p));
        return true;
    case wkbLineString:
        out.type = Geometry::Type::LineString;
        out.lines.push_back(path_of(*g.toLineString()));
        return true;
    case wkbMultiLineString:
        out.type = Geometry::Type::MultiLineString;
        for (const OGRLineString* l : *g.toMultiLineString())
            out.lines.push_back(path_of(*l));
        return true;
    default:
        return false;
    }
}

bool convert_any(const OGRGeometry* g, Geometry& out) {
    if (g == nullptr || g->IsEmpty())
        return false;
    if (!g->hasCurveGeometry())
        return convert(*g, out);
    // Curves: linearise with GDAL's default step, as the trisnap reader does.
    const std::unique_ptr<OGRGeometry> linear(g->getLinearGeometry());
    return linear && convert(*linear, out);
}

} // namespace

LoadedLayer load_layer(const std::string& path, const std::string& layer) {
    GDALAllRegister();
    const GDALDatasetUniquePtr ds(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds)
        throw std::runtime_error(path + ": cannot open: " + CPLGetLastErrorMsg());
    OGRLayer* source = ds->GetLayerByName(layer.c_str());
    if (source == nullptr)
        throw std::runtime_error(path + ": no layer '" + layer + "'");
    LoadedLayer out;
    for (const auto& feature : *source) {
        Feature f;
        f.id = feature->GetFID();
        if (convert_any(feature->GetGeometryRef(), f.geometry))
            out.features.push_back(std::move(f));
        else
            ++out.skipped;
    }
    return out;
}

} // namespace trisnap
