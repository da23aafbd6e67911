#pragma once
// Reading one OGR layer into plain shapes for drawing and measuring.
#include "render/types.hpp"

#include <optional>
#include <string>

namespace trisnap::render {

/// Reads polygons and lines of layer `layer_name` (empty: the only polygon/line layer) of
/// `path`; with `bbox`, only features whose envelope meets it (OGR spatial filter). Curves are
/// linearised, points and empty geometries skipped, Z and M dropped. Shapes come back sorted
/// by key: the integer field `key_field` when given, else the `orig_fid` field when present,
/// else the FID. Points with a NaN or infinite coordinate are skipped. Throws io_error for an
/// unreadable file, argument_error for an unknown or ambiguous layer or an unknown key field.
Layer read_layer(const std::string& path, const std::string& layer_name, const std::optional<Box>& bbox,
                 const std::string& key_field = "");

} // namespace trisnap::render
