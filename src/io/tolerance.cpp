#include "io/tolerance.hpp"

#include "config/errors.hpp"

#include <fmt/format.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trisnap {

double metres_per_degree(double lat)
{
    const double k_equator = 6378137.0 * std::numbers::pi / 180.0;
    return k_equator * std::max(std::cos(lat * std::numbers::pi / 180.0), 1e-3);
}

namespace {

struct LatitudeRange {
    double south = 0.0;
    double north = 0.0;
    double middle() const { return (south + north) / 2; }
};

/// The latitudes the layer's extent spans, honouring the data axis order.
LatitudeRange latitude_range(OGRLayer& layer, const OGRSpatialReference& srs)
{
    OGREnvelope e;
    if (layer.GetExtent(&e, TRUE) != OGRERR_NONE) {
        throw argument_error("--tolerance-m: the layer has no extent to take a latitude from");
    }
    const auto& mapping = srs.GetDataAxisToSRSAxisMapping();
    const bool lat_is_x = srs.EPSGTreatsAsLatLong() && !mapping.empty() && mapping[0] == 1;
    return lat_is_x ? LatitudeRange{e.MinX, e.MaxX} : LatitudeRange{e.MinY, e.MaxY};
}

/// The degrees chosen at latitude phi0 are M cos(phi) / cos(phi0) metres east-west at phi: a
/// warning when that is off by more than 10 % somewhere in the layer (a world layer converted at
/// its middle), else "".
std::string latitude_spread_warning(double metres, double degrees, const LatitudeRange& range)
{
    const double at_middle = metres_per_degree(range.middle());
    const double nearest_equator =
        range.south <= 0 && range.north >= 0 ? 0.0 : std::min(std::abs(range.south), std::abs(range.north));
    const double farthest = std::max(std::abs(range.south), std::abs(range.north));
    const double most = metres_per_degree(nearest_equator) / at_middle;
    const double least = metres_per_degree(farthest) / at_middle;
    if (most <= 1.1 && least >= 0.9) {
        return "";
    }
    return fmt::format("--tolerance-m {}: the layer spans latitudes {:.1f} to {:.1f}; {:.3g} degrees (converted at {:.1f}) "
                       "is {:.3g} m to {:.3g} m east-west across it, more than 10 % off; use a projected CRS, or --tolerance "
                       "in degrees", metres, range.south, range.north, degrees, range.middle(), metres * least, metres * most);
}

} // namespace

double mean_latitude(OGRLayer& layer, const OGRSpatialReference& srs) { return latitude_range(layer, srs).middle(); }

double tolerance_from_metres(double metres, OGRLayer& layer, std::string& note, std::string* warning)
{
    const OGRSpatialReference* srs = layer.GetSpatialRef();
    if (!srs) {
        throw argument_error("--tolerance-m needs a layer with a CRS; give --tolerance in layer units");
    }
    if (!srs->IsGeographic()) {
        const double unit = srs->GetLinearUnits();
        note = fmt::format("{} m = {} layer units ({} m each)", metres, metres / unit, unit);
        return metres / unit;
    }
    const LatitudeRange range = latitude_range(layer, *srs);
    const double lat = range.middle();
    const double degrees = metres / metres_per_degree(lat);
    note = fmt::format("{} m = {:.3g} degrees at mean latitude {:.4f}", metres, degrees, lat);
    if (warning) {
        *warning = latitude_spread_warning(metres, degrees, range);
    }
    return degrees;
}

bool degrees_above_warning(double tolerance, bool from_metres, const OGRSpatialReference* srs)
{
    return !from_metres && srs != nullptr && srs->IsGeographic() && tolerance >= k_degree_warning;
}

namespace {

/// The tolerance as a length on the layer's CRS ("0.01 degrees, about 820 m here": at the layer's
/// mean latitude, as --tolerance-m converts), or in layer units without a CRS. The one figure
/// the warning and the collapse guard both give.
std::string tolerance_length(double tolerance, OGRLayer& layer)
{
    const OGRSpatialReference* srs = layer.GetSpatialRef();
    if (srs == nullptr) {
        return fmt::format("{} layer units (the layer has no CRS)", tolerance);
    }
    if (!srs->IsGeographic()) {
        return fmt::format("{:.3g} m", tolerance * srs->GetLinearUnits());
    }
    OGREnvelope e;
    if (layer.GetExtent(&e, TRUE) != OGRERR_NONE) {
        return fmt::format("{} degrees", tolerance);
    }
    const double metres = tolerance * metres_per_degree(mean_latitude(layer, *srs));
    return fmt::format("{:.3g} degrees, about {:.3g} m here", tolerance, metres);
}

} // namespace

std::string degree_warning(double tolerance, OGRLayer& layer)
{
    return fmt::format("--tolerance {} is in degrees on this geographic CRS ({}); for metres use --tolerance-m",
                       tolerance, tolerance_length(tolerance, layer));
}

std::string collapse_advice(double tolerance, bool from_metres, OGRLayer& layer)
{
    const std::string length = tolerance_length(tolerance, layer);
    if (!degrees_above_warning(tolerance, from_metres, layer.GetSpatialRef())) {
        return fmt::format("the tolerance is {}: give a smaller one", length);
    }
    std::string note;
    tolerance_from_metres(tolerance, layer, note);
    return fmt::format("--tolerance is in degrees on this geographic CRS ({}); you probably meant --tolerance-m {} ({})",
                       length, tolerance, note);
}

namespace {

void check_positive(const char* option, double value)
{
    if (!std::isfinite(value) || value <= 0) {
        throw argument_error(fmt::format("{} must be finite and > 0, got {}", option, value));
    }
}

} // namespace

std::optional<double> tolerance_option(std::optional<double> tolerance, std::optional<double> metres, OGRLayer& layer)
{
    if (tolerance && metres) {
        throw argument_error("give --tolerance or --tolerance-m, not both");
    }
    if (tolerance) {
        check_positive("--tolerance", *tolerance);
        return tolerance;
    }
    if (!metres) {
        return std::nullopt;
    }
    check_positive("--tolerance-m", *metres);
    std::string note;
    return tolerance_from_metres(*metres, layer, note);
}

} // namespace trisnap
