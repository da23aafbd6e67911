#pragma once
// The output formats trisnap refuses, and why: one list (format_limits.cpp). Each of them would
// lose, without a word, what snapping made: it writes no file at all (Memory, databases, web
// services), cannot store a geometry (spreadsheets), quantises coordinates to a grid coarser than
// the tolerance (vector tiles, MapML), or stores WGS84 only and so reprojects, or mislabels, a
// layer in any other CRS after snapping (KML, GPX, GeoJSONSeq, GeoJSON with RFC7946=YES).
// Snapping is done in the layer's CRS: a reprojection afterwards moves every vertex by a
// different amount and breaks the separations, so the advice is to reproject before snapping.
// The checks run before any data is read, so `validate` fails where `snap` would.
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <string>
#include <vector>

namespace trisnap {

/// Why `driver` can never be OUT ("" when it can, maybe only for some layers: layer_refusal).
/// The reason is a clause to follow "the NAME format ".
std::string format_refusal(GDALDriver& driver);

/// Why `driver` cannot be OUT for a layer in `crs` (null: none) with layer creation options
/// `lco`, or "" when it can.
std::string layer_refusal(GDALDriver& driver, const OGRSpatialReference* crs, const std::vector<std::string>& lco);

/// For `trisnap --formats`: the condition a writable driver puts on OUT ("WGS84 layers only"),
/// or "".
std::string format_condition(GDALDriver& driver);

} // namespace trisnap
