#include "io/update_target.hpp"

#include "config/errors.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/output_driver.hpp"

#include <cpl_string.h>

#include <algorithm>
#include <filesystem>

namespace trisnap {
namespace {

bool output_exists(const WriteOptions& options)
{
    std::error_code ec;
    return !is_stdout_path(options.path) && std::filesystem::exists(options.path, ec);
}

/// A source field of this type may go into a target field of that type.
bool fits(OGRFieldType source, OGRFieldType target)
{
    return source == target || (source == OFTInteger && target == OFTInteger64);
}

/// Polygons into a polygon or multipolygon layer (lines likewise), anything into an untyped one.
bool geometry_fits(OGRwkbGeometryType source, OGRwkbGeometryType target)
{
    const OGRwkbGeometryType s = wkbFlatten(source);
    const OGRwkbGeometryType t = wkbFlatten(target);
    return t == wkbUnknown || s == t || (s == wkbPolygon && t == wkbMultiPolygon) ||
           (s == wkbLineString && t == wkbMultiLineString);
}

std::string field_names(const OGRFeatureDefn& defn)
{
    std::string names;
    for (int i = 0; i < defn.GetFieldCount(); ++i) {
        names += (i > 0 ? ", " : "") + std::string(defn.GetFieldDefn(i)->GetNameRef());
    }
    return names.empty() ? "none" : names;
}

/// True when `path` is a dataset `driver` reads (by its header, without opening it).
bool is_dataset_of(const std::string& path, GDALDriver& driver)
{
    const char* const drivers[] = {driver.GetDescription(), nullptr};
    ScopedErrorCapture quiet;
    return GDALIdentifyDriverEx(path.c_str(), GDAL_OF_VECTOR, drivers, nullptr) != nullptr;
}

void check_flags(const WriteOptions& options, GDALDriver& driver)
{
    if (options.overwrite && options.append) {
        throw argument_error("give --overwrite (replace the layer) or --append (add to it), not both");
    }
    if ((options.update || options.append) && !holds_layers(driver)) {
        throw argument_error(options.path + ": the " + std::string(driver.GetDescription()) +
                             " format holds one layer per file: --update and --append need one that holds several "
                             "(GPKG, SQLite); --overwrite replaces the file");
    }
}

/// --append: the existing layer takes the source's geometries and fields.
void check_append(const WriteOptions& options, OGRLayer& target, OGRLayer& source)
{
    const std::string where = options.path + " (layer '" + target.GetName() + "')";
    if (!geometry_fits(source.GetGeomType(), target.GetGeomType())) {
        throw argument_error(where + ": --append: the layer holds " + OGRGeometryTypeToName(target.GetGeomType()) +
                             ", the input " + OGRGeometryTypeToName(source.GetGeomType()));
    }
    append_field_map(*source.GetLayerDefn(), *target.GetLayerDefn(), options.fields, where);
}

} // namespace

bool holds_layers(GDALDriver& driver)
{
    return CPLTestBool(CSLFetchNameValueDef(driver.GetMetadata(), GDAL_DCAP_MULTIPLE_VECTOR_LAYERS, "NO"));
}

bool updates_in_place(const WriteOptions& options, GDALDriver& driver)
{
    if (!(options.overwrite || options.update || options.append) || !holds_layers(driver) || !output_exists(options)) {
        return false;
    }
    // --overwrite of a file that is no dataset of this format (no layers to keep) replaces it.
    return options.update || options.append || is_dataset_of(options.path, driver);
}

std::string output_layer_name(const WriteOptions& options, OGRLayer& source)
{
    return options.layer_name.empty() ? std::string(source.GetName()) : options.layer_name;
}

GDALDatasetUniquePtr open_for_update(const WriteOptions& options, GDALDriver& driver)
{
    const char* const drivers[] = {driver.GetDescription(), nullptr};
    ScopedErrorCapture capture;
    GDALDatasetUniquePtr dataset(
        GDALDataset::Open(options.path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, drivers, nullptr, nullptr));
    if (!dataset) {
        throw io_error(options.path, "", capture.last_error("cannot open it for update as " +
                                                            std::string(driver.GetDescription())));
    }
    return dataset;
}

void check_update_target(const WriteOptions& options, GDALDriver& driver, OGRLayer& source)
{
    check_flags(options, driver);
    if (!updates_in_place(options, driver)) {
        return;
    }
    const GDALDatasetUniquePtr dataset = open_for_update(options, driver);
    const std::string name = output_layer_name(options, source);
    OGRLayer* existing = dataset->GetLayerByName(name.c_str());
    if (existing == nullptr) {
        return;
    }
    if (options.append) {
        check_append(options, *existing, source);
        return;
    }
    if (!options.overwrite) {
        throw argument_error(options.path + ": has a layer '" + name + "' already; add --overwrite to replace it" +
                             (options.renamable ? ", --append to add to it, or -nln NAME" : " or --append to add to it"));
    }
}

std::vector<int> append_field_map(const OGRFeatureDefn& source, const OGRFeatureDefn& target,
                                  const std::vector<std::string>& only, const std::string& where)
{
    std::vector<int> map;
    for (int i = 0; i < source.GetFieldCount(); ++i) {
        const OGRFieldDefn& field = *source.GetFieldDefn(i);
        const std::string name = field.GetNameRef();
        if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) {
            map.push_back(-1);
            continue;
        }
        const int k = target.GetFieldIndex(name.c_str());
        if (k < 0) {
            throw argument_error(where + ": --append: the layer has no field '" + name + "' (its fields: " +
                                 field_names(target) + "); leave it out with --select, or write another layer");
        }
        const OGRFieldType want = target.GetFieldDefn(k)->GetType();
        if (!fits(field.GetType(), want)) {
            throw argument_error(where + ": --append: field '" + name + "' is " + OGRFieldDefn::GetFieldTypeName(want) +
                                 " in the layer, " + OGRFieldDefn::GetFieldTypeName(field.GetType()) + " in the input");
        }
        map.push_back(k);
    }
    return map;
}

} // namespace trisnap
