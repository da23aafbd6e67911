#include "render/types.hpp"

#include <algorithm>
#include <cmath>

namespace trisnap::render {

void Box::add(XY p)
{
    xmin = std::min(xmin, p.x);
    ymin = std::min(ymin, p.y);
    xmax = std::max(xmax, p.x);
    ymax = std::max(ymax, p.y);
}

void Box::add(const Box& b)
{
    if (b.empty()) {
        return;
    }
    add(XY{b.xmin, b.ymin});
    add(XY{b.xmax, b.ymax});
}

bool Box::intersects(const Box& b) const
{
    return !empty() && !b.empty() && xmin <= b.xmax && b.xmin <= xmax && ymin <= b.ymax && b.ymin <= ymax;
}

double distance(XY a, XY b) { return std::hypot(a.x - b.x, a.y - b.y); }

double distance_to_segment(XY p, XY a, XY b, XY* nearest)
{
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const XY q{a.x + t * dx, a.y + t * dy};
    if (nearest) {
        *nearest = q;
    }
    return distance(p, q);
}

} // namespace trisnap::render
