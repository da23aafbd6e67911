#include "io/format_limits.hpp"

#include <cpl_string.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace trisnap {
namespace {

enum class Limit {
    never,      ///< refused for every layer
    wgs84_only, ///< refused for a layer with a CRS other than WGS84 (without a CRS it is written as is)
};

struct Refused {
    const char* driver;
    Limit limit;
    const char* reason; ///< follows "the NAME format "
};

constexpr const char* k_tiles = "writes vector tiles: it quantises the coordinates to each tile's grid (4096 steps "
                                "a tile by default), which undoes the snap, and cuts features at tile edges; write "
                                "GPKG or FlatGeobuf (make tiles from that knowing they are not snapped)";
constexpr const char* k_sheet = "is a spreadsheet: it cannot store the geometries; choose another format (e.g. -f GPKG)";
constexpr const char* k_wgs84 = "stores WGS84 longitude/latitude only";

/// The list. Checked by writing the shared sample with GDAL 3.6 (ogr2ogr): MVT and MBTiles
/// wrote 0 tiles for it; KML, LIBKML and GeoJSONSeq gave lon/lat from EPSG:28992; GPX wrote the
/// metres as latitudes; GeoRSS refuses other CRSs itself; MapML rounds to 2 decimals in metres
/// and 8 in degrees whatever the CRS.
constexpr Refused k_refused[] = {
    {"MVT", Limit::never, k_tiles},
    {"MBTiles", Limit::never, k_tiles},
    {"PMTiles", Limit::never, k_tiles},
    {"MapML", Limit::never, "rounds the coordinates (to 2 decimals in metres, 8 in degrees), which undoes the snap; "
                            "write GPKG, FlatGeobuf or GeoJSON"},
    {"XLSX", Limit::never, k_sheet},
    {"ODS", Limit::never, k_sheet},
    {"KML", Limit::wgs84_only, k_wgs84},
    {"LIBKML", Limit::wgs84_only, k_wgs84},
    {"GeoJSONSeq", Limit::wgs84_only, k_wgs84},
    {"GPX", Limit::wgs84_only, k_wgs84},
    {"GeoRSS", Limit::wgs84_only, k_wgs84},
};

const Refused* find_refused(GDALDriver& driver)
{
    const std::string name = driver.GetDescription();
    const auto* it = std::find_if(std::begin(k_refused), std::end(k_refused),
                                  [&](const Refused& r) { return name == r.driver; });
    return it == std::end(k_refused) ? nullptr : it;
}

/// A geographic CRS without an authority on the WGS84 ellipsoid (GeoPackage's "Undefined
/// geographic SRS", srs_id 0): the drivers' transformation to WGS84 moves nothing (checked: KML
/// wrote the coordinates unchanged).
bool is_undefined_lon_lat(const OGRSpatialReference& crs)
{
    OGRErr err = OGRERR_NONE;
    return crs.IsGeographic() && crs.GetAuthorityName(nullptr) == nullptr && crs.GetSemiMajor(&err) == SRS_WGS84_SEMIMAJOR &&
           std::abs(crs.GetInvFlattening(&err) - SRS_WGS84_INVFLATTENING) < 1e-9;
}

bool is_wgs84(const OGRSpatialReference& crs)
{
    if (is_undefined_lon_lat(crs)) {
        return true;
    }
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    // Longitude/latitude in either axis order: swapping the axes moves no vertex.
    const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
    return crs.IsSame(&wgs84, options) != 0;
}

std::string crs_name(const OGRSpatialReference& crs)
{
    const char* authority = crs.GetAuthorityName(nullptr);
    const char* code = crs.GetAuthorityCode(nullptr);
    if (authority && code) {
        return std::string(authority) + ":" + code;
    }
    const char* name = crs.GetName();
    return name ? name : "its CRS";
}

/// The reprojection that snapping in the layer's CRS cannot survive.
std::string reprojection_refusal(const Refused& r, const OGRSpatialReference& crs)
{
    return std::string(r.reason) + ", and the layer is in " + crs_name(crs) +
           ": GDAL would reproject (or mislabel) the snapped coordinates, and moving them after snapping breaks "
           "the separations snapping made; write GPKG, FlatGeobuf or GeoJSON, or reproject before snapping "
           "(ogr2ogr -t_srs EPSG:4326) and snap that";
}

bool option_is_yes(const std::vector<std::string>& options, const char* key)
{
    CPLStringList list;
    for (const std::string& o : options) {
        list.AddString(o.c_str());
    }
    return CPLTestBool(list.FetchNameValueDef(key, "NO"));
}

} // namespace

std::string format_refusal(GDALDriver& driver)
{
    // trisnap writes files (through its checking file system): a driver without GDAL's virtual
    // I/O writes to memory, a database or a web service, where nothing could be checked or renamed.
    if (driver.GetMetadataItem(GDAL_DCAP_VIRTUALIO) == nullptr) {
        return "writes no file (memory, a database or a service); trisnap writes files, e.g. -f GPKG, FlatGeobuf, "
               "\"ESRI Shapefile\", GeoJSON";
    }
    const Refused* r = find_refused(driver);
    return r && r->limit == Limit::never ? r->reason : "";
}

std::string layer_refusal(GDALDriver& driver, const OGRSpatialReference* crs, const std::vector<std::string>& lco)
{
    if (std::string reason = format_refusal(driver); !reason.empty()) {
        return reason;
    }
    if (std::string(driver.GetDescription()) == "GeoJSON" && option_is_yes(lco, "RFC7946")) {
        return "with --lco RFC7946=YES writes WGS84 rounded to 7 decimals (about 1 cm), which moves the snapped "
               "vertices; leave RFC7946 out (GeoJSON then keeps the layer's CRS and every digit)";
    }
    const Refused* r = find_refused(driver);
    if (r && r->limit == Limit::wgs84_only && crs && !is_wgs84(*crs)) {
        return reprojection_refusal(*r, *crs);
    }
    return "";
}

std::string format_condition(GDALDriver& driver)
{
    const Refused* r = find_refused(driver);
    return r && r->limit == Limit::wgs84_only ? "OUT for WGS84 layers only" : "";
}

} // namespace trisnap
