#include "io/dataset.hpp"

#include "config/errors.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"

#include <cpl_conv.h>
#include <cpl_string.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <vector>

namespace trisnap {
namespace {

bool ends_with(const std::string& s, const std::string& suffix)
{
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void set_default_option(const char* key, const char* value)
{
    if (!CPLGetConfigOption(key, nullptr)) CPLSetConfigOption(key, value);
}

/// The OSM driver keeps node locations in its own index and spills its temporary database to
/// disk beyond OSM_MAX_TMPFILE_SIZE MB; 1 GB in RAM keeps small and medium extracts in memory.
void configure_osm_driver()
{
    set_default_option("OSM_USE_CUSTOM_INDEXING", "YES");
    set_default_option("OSM_COMPRESS_NODES", "YES");
    set_default_option("OSM_MAX_TMPFILE_SIZE", "1024");
    set_default_option("OGR_INTERLEAVED_READING", "YES");
}

} // namespace

bool is_osm_path(const std::string& path)
{
    std::string lower = path;
    std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
    return ends_with(lower, ".osm.pbf") || ends_with(lower, ".pbf") || ends_with(lower, ".osm");
}

bool is_gdal_source_string(const std::string& path)
{
    if (path.rfind("/vsi", 0) == 0) {
        return true;
    }
    // PREFIX:rest with a prefix of two or more letters (one letter is a drive, C:\...).
    const auto colon = path.find(':');
    if (colon == std::string::npos || colon < 2) {
        return false;
    }
    return std::all_of(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(colon),
                       [](unsigned char c) { return std::isalnum(c) != 0 || c == '_'; });
}

GDALDatasetUniquePtr open_input(const std::string& path, const std::vector<std::string>& open_options)
{
    if (!is_gdal_source_string(path) && !std::filesystem::exists(path)) {
        throw io_error(path, "", "no such file or directory");
    }
    if (is_osm_path(path)) {
        configure_osm_driver();
    }
    CPLStringList options;
    for (const std::string& option : open_options) {
        options.AddString(option.c_str());
    }
    ScopedErrorCapture capture;
    GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr,
                                                   options.List()));
    if (!dataset)
        throw io_error(path, "", capture.last_error("not a readable vector dataset (unknown or corrupt format)"));
    if (dataset->GetLayerCount() == 0) throw io_error(path, "", "the dataset has no vector layers");
    return dataset;
}

std::string list_layers(GDALDataset& dataset)
{
    std::string out;
    for (OGRLayer* layer : dataset.GetLayers()) {
        if (!out.empty()) out += ", ";
        out += std::string(layer->GetName()) + " (" + OGRGeometryTypeToName(layer->GetGeomType()) + ")";
    }
    return out;
}

bool is_snappable_layer_type(OGRwkbGeometryType type)
{
    switch (wkbFlatten(type)) {
    case wkbUnknown: // "any geometry": decided per feature
    case wkbPolygon: case wkbMultiPolygon: case wkbCurvePolygon: case wkbMultiSurface:
    case wkbLineString: case wkbMultiLineString: case wkbCompoundCurve: case wkbCircularString:
    case wkbMultiCurve:
        return true;
    default:
        return false;
    }
}

OGRLayer& find_layer(GDALDataset& dataset, const std::string& path, const std::string& name)
{
    OGRLayer* layer = dataset.GetLayerByName(name.c_str());
    if (!layer) throw argument_error(path + ": no layer '" + name + "'; layers: " + list_layers(dataset));
    return *layer;
}

OGRLayer& select_layer(GDALDataset& dataset, const std::string& path, const std::string& name)
{
    OGRLayer* chosen = nullptr;
    if (!name.empty()) {
        chosen = &find_layer(dataset, path, name);
    } else if (dataset.GetLayerCount() == 1) {
        chosen = dataset.GetLayer(0);
    } else {
        std::vector<OGRLayer*> candidates;
        for (OGRLayer* layer : dataset.GetLayers())
            if (is_snappable_layer_type(layer->GetGeomType())) candidates.push_back(layer);
        if (candidates.size() != 1)
            throw argument_error(path + ": " + (candidates.empty() ? "no polygon or line layer" : "several polygon/line layers") +
                                 ", choose one with --layer; layers: " + list_layers(dataset));
        chosen = candidates.front();
    }
    if (!is_snappable_layer_type(chosen->GetGeomType()))
        throw io_error(path, chosen->GetName(),
                       std::string("unsupported geometry type ") + OGRGeometryTypeToName(chosen->GetGeomType()) +
                           ": trisnap snaps polygons and lines (and curves)");
    return *chosen;
}

} // namespace trisnap
