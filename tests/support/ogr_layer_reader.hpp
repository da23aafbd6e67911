#pragma once
// A small test-side GDAL reader: one OGR layer -> trisnap::Feature (FID as id). Independent of
// src/io on purpose, so the real-data tests do not trust the code they could help to debug.
#include "core/geometry.hpp"

#include <string>
#include <vector>

namespace trisnap {

struct LayerData {
    std::vector<Feature> features;
    std::size_t skipped = 0; ///< features with no geometry or a type we do not read
    bool geographic = false; ///< the layer's CRS is geographic (degrees)
};

/// Reads polygons, multipolygons, linestrings and multilinestrings (with Z when present).
/// Throws std::runtime_error naming the dataset and layer when either cannot be opened.
LayerData read_ogr_layer(const std::string& path, const std::string& layer);

} // namespace trisnap
