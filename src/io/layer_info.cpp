#include "io/layer_info.hpp"

#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"

#include <ogrsf_frmts.h>

namespace trisnap {
namespace {

LayerInfo describe_layer(OGRLayer& layer)
{
    LayerInfo info;
    info.name = layer.GetName();
    info.declared_type = OGRGeometryTypeToName(layer.GetGeomType());
    info.geometry_type = layer.GetGeomType();
    const OGRSpatialReference* srs = layer.GetSpatialRef();
    info.crs = describe_crs(srs);
    info.geographic = srs && srs->IsGeographic();
    info.fid_column = layer.GetFIDColumn();
    info.fields = layer.GetLayerDefn()->GetFieldCount();
    return info;
}

void add_feature(LayerInfo& info, const OGRFeature& feature)
{
    const OGRGeometry* g = feature.GetGeometryRef();
    ++info.features;
    ++info.types[g ? OGRGeometryTypeToName(g->getGeometryType()) : "null"];
    info.vertices += static_cast<std::int64_t>(count_vertices(g));
    if (!g || g->IsEmpty()) return;
    OGREnvelope e;
    g->getEnvelope(&e);
    if (!info.has_extent) {
        info.extent[0] = e.MinX, info.extent[1] = e.MinY, info.extent[2] = e.MaxX, info.extent[3] = e.MaxY;
        info.has_extent = true;
        return;
    }
    info.extent[0] = std::min(info.extent[0], e.MinX);
    info.extent[1] = std::min(info.extent[1], e.MinY);
    info.extent[2] = std::max(info.extent[2], e.MaxX);
    info.extent[3] = std::max(info.extent[3], e.MaxY);
}

} // namespace

std::string describe_crs(const OGRSpatialReference* srs)
{
    if (!srs) return "none";
    const char* auth = srs->GetAuthorityName(nullptr);
    const char* code = srs->GetAuthorityCode(nullptr);
    const char* name = srs->GetName();
    std::string out = auth && code ? std::string(auth) + ":" + code : std::string("custom");
    if (name) out += std::string(" (") + name + ")";
    return out;
}

std::vector<LayerInfo> scan_layers(GDALDataset& dataset, OGRLayer* only)
{
    std::vector<LayerInfo> infos;
    std::map<OGRLayer*, std::size_t> index;
    for (OGRLayer* layer : dataset.GetLayers()) {
        if (only && layer != only) continue;
        index[layer] = infos.size();
        infos.push_back(describe_layer(*layer));
    }
    ScopedErrorCapture capture; // a read that stops on an error is a broken file, not the end
    if (only && std::string(dataset.GetDriverName()) != "OSM") {
        only->ResetReading();
        while (OGRFeatureUniquePtr f{only->GetNextFeature()}) add_feature(infos[0], *f);
    } else {
        dataset.ResetReading();
        for (;;) {
            OGRLayer* from = nullptr;
            OGRFeatureUniquePtr f(dataset.GetNextFeature(&from, nullptr, nullptr, nullptr));
            if (!f) break;
            if (auto it = index.find(from); it != index.end()) add_feature(infos[it->second], *f);
        }
    }
    if (!capture.errors().empty()) throw io_error(dataset.GetDescription(), only ? only->GetName() : "", capture.last_error());
    return infos;
}

} // namespace trisnap
