#pragma once
// Tolerances given in metres (`--tolerance-m`), converted to layer units the same way by every
// command that takes one (snap, validate, assess, render), so the same files give the same T.
#include <optional>
#include <string>

class OGRLayer;
class OGRSpatialReference;

namespace trisnap {

/// Metres per degree of longitude at latitude `lat` on a sphere of the WGS84 equator radius
/// (never below a thousandth of the equator's, so a pole gives a finite value).
double metres_per_degree(double lat);

/// A tolerance in degrees at or above this (over 110 m at the equator) is most likely metres
/// typed as --tolerance on a geographic layer: warned about, and any feature it collapses stops
/// the run (app/collapse_guard.hpp).
inline constexpr double k_degree_warning = 0.001;

/// True when `tolerance` is in degrees (the layer's CRS is geographic and the tolerance was not
/// converted from metres) and at least k_degree_warning.
bool degrees_above_warning(double tolerance, bool from_metres, const OGRSpatialReference* srs);

/// The warning for such a tolerance: "--tolerance 0.01 is in degrees on this geographic CRS
/// (0.01 degrees, about 820 m here); for metres use --tolerance-m", with the length the collapse
/// guard's advice gives too (at the layer's mean latitude).
std::string degree_warning(double tolerance, OGRLayer& layer);

/// What to try instead of a tolerance that collapses too much, as a clause for an error line:
/// for degrees above the warning threshold, the same number in metres ("did you mean
/// --tolerance-m 0.01 (= 1.2e-07 degrees at mean latitude 42.5)?"); else the tolerance in
/// metres where the CRS says, and advice to give a smaller one.
std::string collapse_advice(double tolerance, bool from_metres, OGRLayer& layer);

/// The latitude at the middle of the layer's extent, honouring the data axis order. Throws
/// argument_error when the layer has no extent.
double mean_latitude(OGRLayer& layer, const OGRSpatialReference& srs);

/// `metres` in layer units: divided by the CRS's linear unit on a projected CRS, by
/// metres_per_degree(mean latitude) on a geographic one. `note` says how ("0.05 m = ...");
/// `warning` (when given) gets a sentence when the layer spans so much latitude that the metres
/// are off by more than 10 % somewhere, else "". Throws argument_error for a layer without a CRS.
double tolerance_from_metres(double metres, OGRLayer& layer, std::string& note, std::string* warning = nullptr);

/// The tolerance of a command that measures (assess, render): `tolerance` in layer units, or
/// `metres` converted on `layer` as snap converts them; nullopt when neither is given. Throws
/// argument_error for both, or for a value that is not finite and > 0.
std::optional<double> tolerance_option(std::optional<double> tolerance, std::optional<double> metres, OGRLayer& layer);

} // namespace trisnap
