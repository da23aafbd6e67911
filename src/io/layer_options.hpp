#pragma once
// The layer creation options LayerWriter uses (writer.hpp).
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <string>
#include <vector>

namespace trisnap {

/// `given` (--lco K=V) and, for every option `given` does not set and the driver knows, the
/// writer's default: FID and GEOMETRY_NAME as the source's, a fixed DBF_DATE_LAST_UPDATE, 17
/// significant figures for GeoJSON, UTF-8 Shapefiles, FlatGeobuf without a spatial index (input
/// order), CSV geometry as WKT.
std::vector<std::string> creation_options(const std::vector<std::string>& given, GDALDriver& driver, OGRLayer& source);

} // namespace trisnap
