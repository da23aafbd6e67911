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

double mean_latitude(OGRLayer& layer, const OGRSpatialReference& srs)
{
    OGREnvelope e;
    if (layer.GetExtent(&e, TRUE) != OGRERR_NONE) {
        throw argument_error("--tolerance-m: the layer has no extent to take a latitude from");
    }
    const auto& mapping = srs.GetDataAxisToSRSAxisMapping();
    const bool lat_is_x = srs.EPSGTreatsAsLatLong() && !mapping.empty() && mapping[0] == 1;
    return lat_is_x ? (e.MinX + e.MaxX) / 2 : (e.MinY + e.MaxY) / 2;
}

double tolerance_from_metres(double metres, OGRLayer& layer, std::string& note)
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
    const double lat = mean_latitude(layer, *srs);
    const double degrees = metres / metres_per_degree(lat);
    note = fmt::format("{} m = {:.3g} degrees at mean latitude {:.4f}", metres, degrees, lat);
    return degrees;
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
