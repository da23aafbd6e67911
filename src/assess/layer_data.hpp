#pragma once
// A layer read into flat arrays for measuring: every feature's rings and lines as point runs,
// its FID, its match key and the values of the attributes compared between the two layers.
// Read through src/io's LayerReader, the reader `snap` uses (interleaved for OSM). Curves are
// linearised; points and empty geometries give features without parts; a feature with a
// coordinate that is not finite or beyond ±k_max_coordinate keeps no parts and is marked
// unmeasurable (squared distances would overflow).
#include "assess/geometry.hpp"

#include <cstdint>
#include <string>
#include <vector>

class GDALDataset;
class OGRLayer;
class OGRGeometry;

namespace trisnap::assess {

enum class PartType : std::uint8_t { line, shell, hole };

/// pts[begin, end); rings repeat their first point at the end (closed on reading if needed).
struct Part {
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
    PartType type = PartType::line;
};

/// Coordinates beyond this cannot be measured in double arithmetic (their squares overflow).
constexpr double k_max_coordinate = 1e150;

enum class FeatureKind : std::uint8_t { empty, line, polygon, unmeasurable };

struct Feature {
    std::int64_t fid = 0;
    std::string key;                 // FID as text, or the --key field's value
    std::uint32_t part_begin = 0;    // parts[part_begin, part_end)
    std::uint32_t part_end = 0;
    FeatureKind kind = FeatureKind::empty;
    Box box;
    std::vector<std::string> values; // the compared fields, normalised to text
};

struct LayerData {
    std::string name;
    std::vector<Pt> pts;
    std::vector<Part> parts;
    std::vector<Feature> features;
    std::vector<std::string> compared_fields;

    std::size_t segment_count(const Feature& f) const;
    /// A point of the feature for examples (its first vertex; 0,0 when empty).
    Pt anchor(const Feature& f) const;
    /// Area of a polygon feature: shells minus holes (0 for lines).
    double area(const Feature& f) const;
    /// Total length of the feature's rings and lines.
    double length(const Feature& f) const;
    /// The feature's polygons as an OGR geometry (nullptr for lines and empty features).
    OGRGeometry* make_ogr_polygon(const Feature& f) const;
    /// True when p is strictly inside the polygon feature (even-odd over all rings); points on
    /// the boundary count as outside.
    bool strictly_inside(const Feature& f, Pt p) const;
};

/// Reads `layer` of `dataset` (which may name the key field, empty for FIDs; compared fields are
/// read by name). Throws io_error naming the file, layer and FID when GDAL reports an error
/// while reading (a corrupt file).
LayerData read_layer(GDALDataset& dataset, OGRLayer& layer, const std::string& key_field,
                     const std::vector<std::string>& fields);

} // namespace trisnap::assess
