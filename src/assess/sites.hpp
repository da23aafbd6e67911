#pragma once
// Places worth a look, and the one definition of "worst" that `assess` (its list of worst
// sites) and `render` (its --worst panels and overview labels) share, so both name the same
// site first for the same files.
//
// Order: contract breaches nobody explained, then breaches the snap report explains, then
// reported problems, then the largest values within the contract, then overlaps and crossings
// the input had already. Within a tier the kinds take
// turns (missing, invalid, crossing, overlap, gap, drift, vertex-edge, vertex-vertex, problem),
// each kind worst first. A site is skipped when it lies within `spacing` of one already taken
// or concerns a feature one already taken concerns (no feature is shown twice), and, outside
// the breaches, when nothing changed near it.
#include "assess/geometry.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace trisnap::assess {

enum class SiteKind : std::uint8_t { missing, invalid, crossing, overlap, gap, drift, vertex_edge, vertex_vertex, problem };
inline constexpr int k_site_kinds = 9;

/// "missing", "invalid", "crossing", "overlap", "gap", "drift", "vertex-edge", "vertex-vertex",
/// "problem".
const char* site_kind_name(SiteKind kind);

struct Site {
    SiteKind kind = SiteKind::problem;
    Pt at;                  ///< the place: the vertex, the farthest point, the lost feature's centre
    Pt other;               ///< the partner: other vertex, closest point, nearest point of the other side
    double value = 0;       ///< distance, area or length in layer units (missing: mean width 2A/P or length)
    std::int64_t fid = -1;  ///< input FID (missing, drift, gap), else output FID
    std::int64_t fid2 = -1; ///< the other feature of a pair
    int code = 0;           ///< problem code (problem sites)
    std::string name;       ///< problem name; missing: "width" or "length" (what `value` is)
    Box extent;             ///< missing: the lost input feature's box
    bool breach = false;    ///< breaks the contract at T
    std::string excused_by; ///< the snap report's codes that explain it, e.g. "209 thin_part_collapsed"
    bool is_new = true;     ///< overlaps and crossings: false when the input had it already
};

/// A short code for labels: the problem code for problems ("204"), else the kind's name.
std::string site_code(const Site& site);

/// What a site is, in words shared by assess's list and render's panels: "drift 30.7 T (> 2T)",
/// "vertex-edge 0.31 T (< T/2)", "overlap 2.1e-05 (new)", "problem 204 hole_removed".
std::string describe_site(const Site& site, double tolerance);

/// Its features and place: "fid 170 / 171 at 84924.22, 447578.89".
std::string site_place(const Site& site);

/// Sorts by kind, worst first within a kind (largest drift, smallest separation, ...).
void sort_sites(std::vector<Site>& sites);

/// Up to n sites in the shared order (see above). `changed(site)` says whether anything changed
/// near a site; it is asked only outside the breaches.
std::vector<Site> pick_worst(const std::vector<Site>& sites, std::size_t n, double spacing,
                             const std::function<bool(const Site&)>& changed);

} // namespace trisnap::assess
