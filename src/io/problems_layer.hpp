#pragma once
// The problems of a run as a point layer (--problems-layer FILE), to open in QGIS next to the
// output: one point per located problem, unlocated problems as features without geometry.
#include "core/problems.hpp"

#include <ogr_spatialref.h>

#include <functional>
#include <string>
#include <vector>

namespace trisnap {

/// Refuses a FILE whose extension is neither .gpkg nor .geojson/.json, one that exists without
/// `overwrite` (or, for an existing GeoPackage, `update`: then only a layer "problems" in it
/// without `overwrite`), and one in a directory that does not exist. Throws argument_error.
void check_problems_layer_path(const std::string& path, bool overwrite, bool update);

/// Writes layer "problems" with fields fid (the input FID), code, name and message, in `srs`
/// (the input's; may be null), GeoPackage or GeoJSON by extension. Written beside `path` under
/// a hidden name and renamed into place, so a failure leaves nothing at `path`. With `update`
/// (--overwrite, --update, --append) an existing GeoPackage keeps its other layers: "problems"
/// is replaced or added in one transaction, rolled back on failure. With `layers` (the input
/// layers of a run that snapped several) a field "layer" after "fid" holds the name of the
/// layer of each problem's FID (layers[Problem::layer]). Throws io_error.
void write_problems_layer(const std::string& path, const std::vector<Problem>& problems,
                          OGRSpatialReference* srs, bool update = false,
                          const std::vector<std::string>& layers = {});

/// Calls its argument with each problem, in order (a run's log read back from its work files).
using ProblemSource = std::function<void(const std::function<void(const Problem&)>&)>;

/// The same, the problems one at a time from `problems` (never all in memory).
void write_problems_layer(const std::string& path, const ProblemSource& problems, OGRSpatialReference* srs,
                          bool update = false, const std::vector<std::string>& layers = {});

} // namespace trisnap
