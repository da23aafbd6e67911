// The layer creation options the writer passes to GDAL: the user's, then defaults that keep
// the output like the input (FID and geometry column names) and repeatable and exact (dates,
// digits, encoding, input order), each only where the driver knows the option and the user did
// not give it.
#include "io/layer_options.hpp"

#include <cpl_string.h>

#include <algorithm>

namespace trisnap {
namespace {

bool has_option(const std::vector<std::string>& options, const std::string& key)
{
    return std::any_of(options.begin(), options.end(), [&](const std::string& o) {
        return o.size() > key.size() && o[key.size()] == '=' && EQUALN(o.c_str(), key.c_str(), key.size());
    });
}

bool driver_has_layer_option(GDALDriver& driver, const std::string& key)
{
    const char* list = driver.GetMetadataItem(GDAL_DS_LAYER_CREATIONOPTIONLIST);
    return list && std::string(list).find("name='" + key + "'") != std::string::npos;
}

/// Adds KEY=VALUE unless the user gave KEY, when the driver knows KEY.
void add_default(std::vector<std::string>& options, GDALDriver& driver, const std::string& key,
                 const std::string& value)
{
    if (!has_option(options, key) && driver_has_layer_option(driver, key)) {
        options.push_back(key + "=" + value);
    }
}

} // namespace

std::vector<std::string> creation_options(const std::vector<std::string>& given, GDALDriver& driver, OGRLayer& source)
{
    std::vector<std::string> options = given;
    const std::string driver_name = driver.GetDescription();
    const std::string fid_column = source.GetFIDColumn();
    if (!fid_column.empty()) {
        add_default(options, driver, "FID", fid_column);
    }
    const std::string geometry_column = source.GetGeometryColumn();
    if (!geometry_column.empty()) {
        add_default(options, driver, "GEOMETRY_NAME", geometry_column);
    }
    // Shapefiles stamp today's date in the .dbf header; a fixed date makes bytes repeatable.
    add_default(options, driver, "DBF_DATE_LAST_UPDATE", "2000-01-01");
    // GeoJSON defaults to 15 significant digits, which can move snapped vertices; keep them exact.
    // GeoJSONSeq rounds to 7 decimals (RFC 7946) unless its COORDINATE_PRECISION is -1.
    if (!has_option(options, "COORDINATE_PRECISION")) {
        add_default(options, driver, "SIGNIFICANT_FIGURES", "17");
        if (driver_name == "GeoJSONSeq") {
            add_default(options, driver, "COORDINATE_PRECISION", "-1");
        }
    }
    // OGR hands us UTF-8; without this the Shapefile driver would recode to ISO-8859-1.
    if (driver_name == "ESRI Shapefile") {
        add_default(options, driver, "ENCODING", "UTF-8");
    }
    // FlatGeobuf's spatial index sorts features along a Hilbert curve; without it they stay in input order.
    if (driver_name == "FlatGeobuf") {
        add_default(options, driver, "SPATIAL_INDEX", "NO");
    }
    // CSV drops geometries unless told where to put them: as WKT in a column, like ogr2ogr -lco.
    if (driver_name == "CSV") {
        add_default(options, driver, "GEOMETRY", "AS_WKT");
    }
    return options;
}

} // namespace trisnap
