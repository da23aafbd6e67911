#pragma once
// Opening input datasets and choosing the layer to snap.
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <string>
#include <vector>

namespace trisnap {

/// True for OpenStreetMap inputs (.osm, .pbf), read through GDAL's OSM driver.
bool is_osm_path(const std::string& path);

/// True for what GDAL opens that is not a plain file name: connection strings ("PG:...",
/// "WFS:...", "OCI:..."), virtual file systems ("/vsizip/...", "/vsicurl/...").
bool is_gdal_source_string(const std::string& path);

/// Opens `path` read-only as a vector dataset, with GDAL open options (`-oo K=V`). For OSM
/// inputs sets the driver's options for large files first (custom indexing, temp file size)
/// unless the user set them. Throws io_error with GDAL's message for a missing, unreadable or
/// unrecognised file ("no such file" only for a plain file name that does not exist).
GDALDatasetUniquePtr open_input(const std::string& path, const std::vector<std::string>& open_options = {});

/// The layer named `name`, or (empty name) the only layer that can hold polygons or lines.
/// Throws argument_error listing the layers when the name is unknown or the choice ambiguous,
/// io_error when the layer holds only points or no geometry at all.
OGRLayer& select_layer(GDALDataset& dataset, const std::string& path, const std::string& name);

/// The layer named `name`; throws argument_error listing the layers when there is none.
OGRLayer& find_layer(GDALDataset& dataset, const std::string& path, const std::string& name);

/// "name (Multi Polygon), other (Point)" for error messages.
std::string list_layers(GDALDataset& dataset);

/// True when features of this declared type may be snapped (polygons, lines, curves, unknown).
bool is_snappable_layer_type(OGRwkbGeometryType type);

} // namespace trisnap
