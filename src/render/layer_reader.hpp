#pragma once
// Reading one OGR layer into plain shapes for drawing and measuring.
#include "render/types.hpp"

#include <optional>
#include <string>

namespace trisnap::render {

/// Reads polygons and lines of layer `layer_name` (empty: the only polygon/line layer) of
/// `path`; with `bbox`, only features whose envelope meets it (OGR spatial filter). Curves are
/// linearised, points and empty geometries skipped, Z and M dropped. Shapes come back sorted
/// by key (FID, or the `orig_fid` field when present). Throws io_error for an unreadable file,
/// argument_error for an unknown or ambiguous layer.
Layer read_layer(const std::string& path, const std::string& layer_name, const std::optional<Box>& bbox);

} // namespace trisnap::render
