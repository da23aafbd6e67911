#pragma once
// Streaming reader: OGR features in, engine features and problems out, one at a time.
// Attributes stay in the OGRFeature (geometry removed when the engine takes it) so the writer
// can put them back unchanged. Bad geometry never throws: it becomes a Problem.
#include "core/geometry.hpp"
#include "core/problems.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <optional>
#include <string>
#include <vector>

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
/// (the driver's required interleaved mode) from the start of the file, with only the layers of
/// `interest` "interesting" (default: `layer` alone) and the others' features skipped. Several
/// layers of one OSM file are read one after the other, a pass over the file each (one reader
/// at a time per dataset), each pass with all of them of interest: after a pass with only
/// `lines` of interest, GDAL 3.6's driver gave no `multipolygons` at all.
class LayerReader {
public:
    LayerReader(GDALDataset& dataset, OGRLayer& layer, const std::vector<OGRLayer*>& interest = {});
    /// The next feature, or nullopt at the end. Never throws for bad geometry: a geometry the
    /// driver failed to read (an error and no geometry) is problem 110, the feature rejected.
    std::optional<InputFeature> next();
    /// The next OGR feature as the driver gives it (no conversion), or null at the end. Throws
    /// io_error when the driver stops on an error.
    OGRFeatureUniquePtr next_raw();
    /// GDAL's error while reading the feature next_raw() returned last, or "" when there was none.
    const std::string& feature_error() const { return m_feature_error; }
    /// next_raw() for the tools that measure geometry themselves (assess, render): an error GDAL
    /// reports while reading a feature is an io_error naming its FID (a corrupt file is not data).
    OGRFeatureUniquePtr next_strict();
    /// Features the driver reports, or -1 when counting needs a full read (e.g. OSM).
    std::int64_t count_hint() const { return m_count_hint; }

private:
    OGRFeatureUniquePtr next_ogr_feature();
    GDALDataset& m_dataset;
    OGRLayer& m_layer;
    bool m_interleaved = false;
    std::int64_t m_count_hint = -1;
    std::string m_feature_error;
};

/// Converts one OGR feature (takes ownership) into an InputFeature.
InputFeature classify_feature(OGRFeatureUniquePtr feature);

} // namespace trisnap
