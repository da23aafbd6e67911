#pragma once
// Fixtures for the assess tests: small layers written with GDAL (in memory or as GeoPackage),
// each feature given by FID, WKT and a name, so every test states its known answer in plain
// coordinates.
#include "assess/assess.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cstdint>
#include <string>
#include <vector>

namespace trisnap::test {

struct Item {
    std::int64_t fid;
    std::string wkt; // "" = no geometry
    std::string name = "";
};

/// A dataset holding one layer "l" with a String field "name" and the items at their FIDs.
/// `driver` "Memory" (path ignored) or "GPKG".
GDALDatasetUniquePtr make_layer(const std::vector<Item>& items, OGRwkbGeometryType type = wkbUnknown,
                                const std::string& driver = "Memory", const std::string& path = "");

/// assess_layers on two in-memory layers.
AssessReport assess_items(const std::vector<Item>& in, const std::vector<Item>& out, double tolerance,
                          const std::string& key = "");

/// assess_layers on two in-memory layers, with every option (e.g. a snap report's excuses).
AssessReport assess_items(const std::vector<Item>& in, const std::vector<Item>& out, const AssessOptions& options);

/// A square as WKT.
std::string square(double x0, double y0, double size);

} // namespace trisnap::test
