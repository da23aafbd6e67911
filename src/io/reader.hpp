#pragma once
// Streaming reader: OGR features in, engine features and problems out, one at a time.
// Attributes stay in the OGRFeature (geometry removed when the engine takes it) so the writer
// can put them back unchanged. Bad geometry never throws: it becomes a Problem.
#include "core/geometry.hpp"
#include "core/problems.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <optional>

namespace trisnap {

/// One input feature after reading.
struct InputFeature {
    std::int64_t fid = OGRNullFID;
    OGRFeatureUniquePtr feature;      ///< attributes; geometry kept only for pass-through features
    OGRwkbGeometryType input_type = wkbUnknown; ///< flattened, linear type of the input geometry
    std::optional<Geometry> geometry; ///< set when the engine should snap it
    std::optional<Problem> problem;   ///< set when something about the input is reported
    bool rejected = false;            ///< true when the feature is not written (problem says why)
};

/// Reads one layer in order. For OSM datasets it reads through GDALDataset::GetNextFeature
/// with only the chosen layer "interesting", the driver's required interleaved mode.
class LayerReader {
public:
    LayerReader(GDALDataset& dataset, OGRLayer& layer);
    /// The next feature, or nullopt at the end. Never throws for bad geometry.
    std::optional<InputFeature> next();
    /// The next feature as the driver gives it, geometry included, or null at the end: for the
    /// tools that measure geometry themselves (assess, render). Throws io_error naming the FID
    /// when GDAL reports an error while reading it (a corrupt file is not read as data).
    OGRFeatureUniquePtr next_raw();
    /// Features the driver reports, or -1 when counting needs a full read (e.g. OSM).
    std::int64_t count_hint() const { return m_count_hint; }

private:
    OGRFeatureUniquePtr next_ogr_feature();
    GDALDataset& m_dataset;
    OGRLayer& m_layer;
    bool m_interleaved = false;
    std::int64_t m_count_hint = -1;
};

/// Converts one OGR feature (takes ownership) into an InputFeature.
InputFeature classify_feature(OGRFeatureUniquePtr feature);

} // namespace trisnap
