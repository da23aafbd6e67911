#include "render/sites.hpp"

#include <algorithm>

namespace trisnap::render {

XY site_centre(const Site& s)
{
    if (s.kind == SiteKind::missing && !s.extent.empty()) {
        return xy(s.extent.centre());
    }
    return {(s.at.x + s.other.x) / 2, (s.at.y + s.other.y) / 2};
}

double panel_half_size(const Site& site, double tolerance)
{
    const double t = tolerance;
    switch (site.kind) {
    case SiteKind::missing: return std::max(site.extent.xmax - site.extent.xmin, site.extent.ymax - site.extent.ymin) * 0.75 + 4 * t;
    case SiteKind::drift: return std::max(6 * t, 2.5 * site.value);
    case SiteKind::vertex_edge:
    case SiteKind::vertex_vertex: return std::max(6 * t, 5 * site.value);
    default: return 8 * t;
    }
}

} // namespace trisnap::render
