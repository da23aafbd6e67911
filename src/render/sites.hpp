#pragma once
// The places render marks are assess's sites (src/assess/sites.hpp): measured by assess on the
// same layers, ranked by the same definition of "worst", so `render --worst N` shows the sites
// `assess` lists, in its order. What is left here is how much room a panel gives a site.
#include "assess/sites.hpp"
#include "render/types.hpp"

namespace trisnap::render {

using assess::Site;
using assess::SiteKind;
using assess::k_site_kinds;

inline XY xy(assess::Pt p) { return {p.x, p.y}; }

/// Where a panel is centred: the lost feature's box centre, else midway between the two points.
XY site_centre(const Site& site);

/// Half the side of the square a panel shows around `site`.
double panel_half_size(const Site& site, double tolerance);

} // namespace trisnap::render
