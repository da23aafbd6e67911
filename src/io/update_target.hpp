#pragma once
// Writing into an existing datasource, as ogr2ogr does with -overwrite, -update and -append:
// on a format that holds several layers in one file (GeoPackage, SQLite), an existing OUT is
// opened for update and only the output layer changes (replaced with --overwrite, added with
// --update, added to with --append); its other layers stay as they are. Everything the run
// changes in OUT (deleting the old layer, creating the new one, every feature) is one
// transaction of the datasource, committed at the end of the write phase: a failed, refused or
// interrupted write rolls it back and leaves OUT as it was (a killed process leaves SQLite's
// journal, which restores it at the next open). On a single-layer format (GeoJSON, Shapefile,
// FlatGeobuf, ...) --overwrite replaces the whole file as before, and --update/--append are
// refused. A new OUT is always written to a temporary and renamed into place (writer.hpp).
#include "io/writer.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <string>
#include <vector>

namespace trisnap {

/// True when the driver keeps several vector layers in one file (DCAP_MULTIPLE_VECTOR_LAYERS).
bool holds_layers(GDALDriver& driver);

/// True when the run writes into the existing OUT in its transaction: OUT exists, the driver
/// holds layers, and --update or --append was given, or --overwrite and OUT is a dataset of
/// that driver (a file that is not, such as an empty or foreign one, is replaced whole).
bool updates_in_place(const WriteOptions& options, GDALDriver& driver);

/// The output layer's name: -nln, else the source layer's.
std::string output_layer_name(const WriteOptions& options, OGRLayer& source);

/// The checks that need no writing, before any data is read: --overwrite with --append, --update
/// or --append on a single-layer format, OUT not openable for update, the output layer already
/// there without --overwrite or --append, and (--append) the layer's fields and geometry type
/// against the source's. Throws argument_error (io_error when OUT cannot be opened).
void check_update_target(const WriteOptions& options, GDALDriver& driver, OGRLayer& source);

/// Opens OUT for update with `driver` only. Throws io_error.
GDALDatasetUniquePtr open_for_update(const WriteOptions& options, GDALDriver& driver);

/// For --append: the index in `target` of each source field (-1: not written, --select), by
/// name. Throws argument_error naming the field for a missing field or a different type.
std::vector<int> append_field_map(const OGRFeatureDefn& source, const OGRFeatureDefn& target,
                                  const std::vector<std::string>& only, const std::string& where);

} // namespace trisnap
