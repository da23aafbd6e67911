#pragma once
// Reading what render draws and measures: the layers through assess's reader (src/io's
// LayerReader, as `snap` reads: interleaved for OSM), once, kept both as assess's flat arrays
// (measured) and as shapes (drawn); the tolerance as `snap` resolves it; the snap report.
#include "assess/layer_pair.hpp"
#include "assess/snap_report.hpp"
#include "io/file_safety.hpp"
#include "render/render.hpp"
#include "render/types.hpp"

#include <optional>

namespace trisnap::render {

struct Inputs {
    assess::LayerPair data;   ///< IN and SNAPPED (IN twice without SNAPPED), for assess
    Layer in;                 ///< drawn thin
    std::optional<Layer> out; ///< drawn bold
    std::optional<double> tolerance;
    std::optional<assess::SnapReport> report;
    ProtectedFiles protect;   ///< every file of IN and SNAPPED, and the report: never the picture
};

/// Reads IN (and SNAPPED) with --bbox applied as an OGR spatial filter; T from --tolerance,
/// --tolerance-m (converted on IN) or the report. Throws io_error for an unreadable file or a
/// layer with no feature read, argument_error for an unknown or ambiguous layer or key field,
/// and, before reading any feature, for a picture path that is a file of IN, SNAPPED or the
/// report under any name (symlink, hard link), a directory or a device.
Inputs read_inputs(const RenderOptions& options);

} // namespace trisnap::render
