#pragma once
// What `trisnap info` and `validate` print about a layer: types, counts, CRS, extent, vertices.
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace trisnap {

struct LayerInfo {
    std::string name;
    std::string declared_type;                 ///< the layer's geometry type, for people
    OGRwkbGeometryType geometry_type = wkbUnknown;
    std::map<std::string, std::int64_t> types; ///< features per geometry type ("null" for none)
    std::int64_t features = 0;
    std::int64_t vertices = 0;
    std::string crs;                           ///< "EPSG:4326 (WGS 84)", or "none"
    bool geographic = false;
    bool has_extent = false;
    double extent[4] = {0, 0, 0, 0};           ///< xmin, ymin, xmax, ymax
    std::string fid_column;
    int fields = 0;
};

/// The CRS as "AUTH:CODE (name)" or "none".
std::string describe_crs(const OGRSpatialReference* srs);

/// Counts everything by reading the layers once (through the dataset for OSM inputs, whose
/// driver needs interleaved reading). With `only`, describes that layer alone.
std::vector<LayerInfo> scan_layers(GDALDataset& dataset, OGRLayer* only = nullptr);

} // namespace trisnap
