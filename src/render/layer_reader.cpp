#include "render/layer_reader.hpp"

#include "config/errors.hpp"
#include "io/dataset.hpp"
#include "io/gdal_errors.hpp"

#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace trisnap::render {
namespace {

std::vector<XY> ring_points(const OGRSimpleCurve& curve)
{
    std::vector<XY> points;
    points.reserve(static_cast<std::size_t>(curve.getNumPoints()));
    for (int i = 0; i < curve.getNumPoints(); ++i) {
        const XY p{curve.getX(i), curve.getY(i)};
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue; // cannot be drawn or measured
        if (points.empty() || !(points.back() == p)) points.push_back(p);
    }
    return points;
}

void add_geometry(const OGRGeometry& geometry, Shape& shape)
{
    const OGRwkbGeometryType type = wkbFlatten(geometry.getGeometryType());
    if (type == wkbPolygon) {
        shape.polygon = true;
        for (const OGRLinearRing* ring : *geometry.toPolygon())
            if (auto points = ring_points(*ring); points.size() >= 2) shape.rings.push_back(std::move(points));
    } else if (type == wkbLineString) {
        shape.polygon = false;
        if (auto points = ring_points(*geometry.toLineString()); points.size() >= 2)
            shape.rings.push_back(std::move(points));
    } else if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
        for (const OGRGeometry* part : *geometry.toGeometryCollection()) add_geometry(*part, shape);
    } else if (geometry.hasCurveGeometry()) {
        std::unique_ptr<OGRGeometry> linear(geometry.getLinearGeometry());
        if (linear) add_geometry(*linear, shape);
    }
}

CrsInfo crs_info(const OGRSpatialReference* srs)
{
    CrsInfo info;
    if (!srs) return info;
    if (srs->IsGeographic()) {
        info.kind = CrsInfo::Kind::geographic;
        info.unit = "deg";
    } else if (srs->IsProjected()) {
        info.kind = CrsInfo::Kind::projected;
        const char* name = nullptr;
        info.metres_per_unit = srs->GetLinearUnits(&name);
        info.unit = info.metres_per_unit == 1.0 ? "m" : (name ? name : "units");
    }
    return info;
}

std::int64_t key_of(OGRFeature& feature, int key_field)
{
    if (key_field >= 0 && feature.IsFieldSetAndNotNull(key_field))
        return feature.GetFieldAsInteger64(key_field);
    return feature.GetFID();
}

int key_field_index(OGRLayer& layer, const std::string& path, const std::string& key_field)
{
    OGRFeatureDefn* defn = layer.GetLayerDefn();
    if (key_field.empty()) return defn->GetFieldIndex("orig_fid");
    const int index = defn->GetFieldIndex(key_field.c_str());
    if (index < 0) {
        std::string fields;
        for (int i = 0; i < defn->GetFieldCount(); ++i) fields += (i ? ", " : "") + std::string(defn->GetFieldDefn(i)->GetNameRef());
        throw argument_error(path + " (layer '" + layer.GetName() + "'): --key: no field '" + key_field +
                             "'; fields: " + (fields.empty() ? "none" : fields));
    }
    return index;
}

} // namespace

Layer read_layer(const std::string& path, const std::string& layer_name, const std::optional<Box>& bbox,
                 const std::string& key_field)
{
    GDALDatasetUniquePtr dataset = open_input(path);
    OGRLayer& ogr_layer = select_layer(*dataset, path, layer_name);
    Layer layer;
    layer.path = path;
    layer.name = ogr_layer.GetName();
    layer.crs = crs_info(ogr_layer.GetSpatialRef());
    if (bbox) ogr_layer.SetSpatialFilterRect(bbox->xmin, bbox->ymin, bbox->xmax, bbox->ymax);
    const int key_index = key_field_index(ogr_layer, path, key_field);
    ScopedErrorCapture capture; // unreadable features are skipped, not printed
    ogr_layer.ResetReading();
    for (OGRFeatureUniquePtr feature(ogr_layer.GetNextFeature()); feature; feature.reset(ogr_layer.GetNextFeature())) {
        const OGRGeometry* geometry = feature->GetGeometryRef();
        if (!geometry || geometry->IsEmpty()) continue;
        Shape shape;
        shape.key = key_of(*feature, key_index);
        add_geometry(*geometry, shape);
        if (shape.rings.empty()) continue;
        for (const auto& ring : shape.rings)
            for (XY p : ring) shape.box.add(p);
        layer.extent.add(shape.box);
        layer.shapes.push_back(std::move(shape));
    }
    std::stable_sort(layer.shapes.begin(), layer.shapes.end(),
                     [](const Shape& a, const Shape& b) { return a.key < b.key; });
    return layer;
}

} // namespace trisnap::render
