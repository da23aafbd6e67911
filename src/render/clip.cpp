#include "render/clip.hpp"

#include <array>
#include <cmath>

namespace trisnap::render {
namespace {

/// One of the four half-planes of the box: inside test and crossing point.
struct Side {
    int axis;     // 0: x, 1: y
    double limit;
    bool keep_below;
    bool inside(XY p) const { return keep_below ? coord(p) <= limit : coord(p) >= limit; }
    double coord(XY p) const { return axis == 0 ? p.x : p.y; }
    XY cross(XY a, XY b) const
    {
        const double t = (limit - coord(a)) / (coord(b) - coord(a));
        XY q{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        (axis == 0 ? q.x : q.y) = limit;
        return q;
    }
};

/// The parameter range [t0, t1] of segment ab inside the box, or false.
bool liang_barsky(XY a, XY b, const Box& box, double& t0, double& t1)
{
    t0 = 0;
    t1 = 1;
    const double dx = b.x - a.x, dy = b.y - a.y;
    const std::array<double, 4> p{-dx, dx, -dy, dy};
    const std::array<double, 4> q{a.x - box.xmin, box.xmax - a.x, a.y - box.ymin, box.ymax - a.y};
    for (std::size_t i = 0; i < 4; ++i) {
        if (p[i] == 0) {
            if (q[i] < 0) {
                return false;
            }
            continue;
        }
        const double t = q[i] / p[i];
        if (p[i] < 0) {
            t0 = std::max(t0, t);
        } else {
            t1 = std::min(t1, t);
        }
    }
    return t0 <= t1;
}

} // namespace

std::vector<XY> clip_ring(const std::vector<XY>& ring, const Box& box)
{
    std::vector<XY> current = ring, next;
    if (!current.empty() && current.front() == current.back()) {
        current.pop_back();
    }
    const std::array<Side, 4> sides{Side{0, box.xmin, false}, Side{0, box.xmax, true}, Side{1, box.ymin, false},
                                    Side{1, box.ymax, true}};
    for (const Side& side : sides) {
        next.clear();
        for (std::size_t i = 0; i < current.size(); ++i) {
            const XY a = current[i], b = current[(i + 1) % current.size()];
            if (side.inside(a)) {
                next.push_back(a);
                if (!side.inside(b)) {
                    next.push_back(side.cross(a, b));
                }
            } else if (side.inside(b)) {
                next.push_back(side.cross(a, b));
            }
        }
        current.swap(next);
        if (current.empty()) {
            break;
        }
    }
    return current;
}

std::vector<std::vector<XY>> clip_line(const std::vector<XY>& line, const Box& box)
{
    std::vector<std::vector<XY>> pieces;
    bool open = false; // the last piece ends where the next segment starts
    for (std::size_t i = 1; i < line.size(); ++i) {
        double t0, t1;
        const XY a = line[i - 1], b = line[i];
        if (!liang_barsky(a, b, box, t0, t1)) {
            open = false;
            continue;
        }
        const XY p{a.x + t0 * (b.x - a.x), a.y + t0 * (b.y - a.y)};
        const XY q{a.x + t1 * (b.x - a.x), a.y + t1 * (b.y - a.y)};
        if (!open || t0 > 0) {
            pieces.push_back({p});
        }
        pieces.back().push_back(q);
        open = t1 >= 1;
    }
    return pieces;
}

std::vector<XY> drop_close_points(const std::vector<XY>& points, double min_step)
{
    std::vector<XY> kept;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const bool last = i + 1 == points.size();
        if (kept.empty() || distance(kept.back(), points[i]) >= min_step) {
            kept.push_back(points[i]);
        } else if (last && kept.size() > 1) {
            kept.back() = points[i];
        } else if (last) {
            kept.push_back(points[i]);
        }
    }
    return kept;
}

} // namespace trisnap::render
