#pragma once
// Reads one OGR layer into the engine's plain features, for benchmarks on real data. Loading
// happens outside the timed loops, so this favours simplicity over speed.
#include "core/geometry.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace trisnap {

struct LoadedLayer {
    std::vector<Feature> features; ///< ids are the OGR FIDs
    std::size_t skipped = 0;       ///< null geometries and types the engine does not take
};

/// Polygons, multipolygons, linestrings and multilinestrings of `layer` in the dataset at `path`
/// (curves linearised, M dropped, Z kept). Throws std::runtime_error naming the dataset and
/// layer when either cannot be opened.
LoadedLayer load_layer(const std::string& path, const std::string& layer);

} // namespace trisnap
