#include "ogr_layer_reader.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <memory>
#include <stdexcept>

namespace trisnap {
namespace {

Path to_path(const OGRSimpleCurve& curve, bool has_z) {
    Path path;
    path.reserve(static_cast<std::size_t>(curve.getNumPoints()));
    for (int i = 0; i < curve.getNumPoints(); ++i) {
        Coord c{curve.getX(i), curve.getY(i)};
        if (has_z)
            c.z = curve.getZ(i);
        path.push_back(c);
    }
    return path;
}

Polygon to_polygon(const OGRPolygon& polygon, bool has_z) {
    Polygon out;
    if (const OGRLinearRing* shell = polygon.getExteriorRing())
        out.rings.push_back(to_path(*shell, has_z));
    for (int i = 0; i < polygon.getNumInteriorRings(); ++i)
        out.rings.push_back(to_path(*polygon.getInteriorRing(i), has_z));
    return out;
}

/// False when the type is not one the engine snaps.
bool to_geometry(const OGRGeometry& g, Geometry& out) {
    out.has_z = g.Is3D();
    switch (wkbFlatten(g.getGeometryType())) {
    case wkbPolygon:
        out.type = Geometry::Type::Polygon;
        out.polygons.push_back(to_polygon(*g.toPolygon(), out.has_z));
        return true;
    case wkbMultiPolygon:
        out.type = Geometry::Type::MultiPolygon;
        for (const OGRPolygon* p : *g.toMultiPolygon())
            out.polygons.push_back(to_polygon(*p, out.has_z));
        return true;
    case wkbLineString:
        out.type = Geometry::Type::LineString;
        out.lines.push_back(to_path(*g.toLineString(), out.has_z));
        return true;
    case wkbMultiLineString:
        out.type = Geometry::Type::MultiLineString;
        for (const OGRLineString* l : *g.toMultiLineString())
            out.lines.push_back(to_path(*l, out.has_z));
        return true;
    default:
        return false;
    }
}

} // namespace

LayerData read_ogr_layer(const std::string& path, const std::string& layer_name) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!ds)
        throw std::runtime_error(path + ": cannot open: " + CPLGetLastErrorMsg());
    OGRLayer* layer = ds->GetLayerByName(layer_name.c_str());
    if (!layer)
        throw std::runtime_error(path + ": no layer " + layer_name);
    LayerData data;
    const OGRSpatialReference* srs = layer->GetSpatialRef();
    data.geographic = srs && srs->IsGeographic();
    for (const auto& feature : *layer) {
        const OGRGeometry* g = feature->GetGeometryRef();
        Feature f{feature->GetFID(), {}};
        if (!g || g->IsEmpty() || !to_geometry(*g, f.geometry)) {
            ++data.skipped;
            continue;
        }
        data.features.push_back(std::move(f));
    }
    return data;
}

} // namespace trisnap
