#pragma once
// What an output driver can do, checked before any data is read (so `validate` fails where
// `snap` would): write vectors, stream to stdout, create the layer and fields at all.
#include "io/writer.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <string>

namespace trisnap {

/// True for OUT "/vsistdout/..." (the CLI turns "-" into "/vsistdout/").
bool is_stdout_path(const std::string& path);

/// True when the driver has a vector writer (GDAL's DCAP_VECTOR and DCAP_CREATE).
bool can_write_vector(GDALDriver& driver);

/// True when the driver writes front to back and so can stream to stdout (GeoJSON,
/// GeoJSONSeq, FlatGeobuf); GPKG, Shapefile and most others need to seek.
bool can_stream(GDALDriver& driver);

/// The /vsistdout/ name to create: some drivers (FlatGeobuf) need their extension on it.
std::string stdout_dataset_path(GDALDriver& driver);

/// Creates the dataset, layer and fields the writer would create, in memory (/vsimem/), and
/// deletes them: a driver that cannot hold this layer's geometry type (GPX and polygons), a bad
/// creation option or an unknown --select field fail here, and so does a format refused for this
/// layer's CRS or options (io/format_limits.hpp). Throws argument_error.
void probe_output(GDALDriver& driver, const WriteOptions& options, OGRLayer& source);

} // namespace trisnap
