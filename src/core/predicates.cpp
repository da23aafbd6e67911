#include "core/predicates.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>

namespace trisnap {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_2 point(const Coord& c) { return Kernel::Point_2(c.x, c.y); }

// Below the horizontal through v, or on it to the left of v: the half turn [pi, 2pi).
bool lower_half(const Coord& v, const Coord& a) { return a.y < v.y || (a.y == v.y && a.x < v.x); }

// p on the closed segment a-b (exact).
bool on_segment(const Coord& a, const Coord& b, const Coord& p)
{
    const bool in_box = std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
                        std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
    return in_box && orientation(a, b, p) == 0;
}

} // namespace

int orientation(const Coord& p, const Coord& q, const Coord& r)
{
    switch (CGAL::orientation(point(p), point(q), point(r))) {
    case CGAL::LEFT_TURN:
        return 1;
    case CGAL::RIGHT_TURN:
        return -1;
    default:
        return 0;
    }
}

bool direction_less(const Coord& v, const Coord& a, const Coord& b)
{
    const bool ha = lower_half(v, a);
    const bool hb = lower_half(v, b);
    if (ha != hb) {
        return hb;
    }
    return orientation(v, a, b) > 0;
}

bool segment_meets_box(const Coord& p, const Coord& q, double xmin, double ymin, double xmax, double ymax)
{
    const double x0 = std::max(xmin, std::min(p.x, q.x));
    const double x1 = std::min(xmax, std::max(p.x, q.x));
    const double y0 = std::max(ymin, std::min(p.y, q.y));
    const double y1 = std::min(ymax, std::max(p.y, q.y));
    if (x0 > x1 || y0 > y1) {
        return false; // the boxes miss each other
    }
    const auto inside = [&](const Coord& c) { return xmin <= c.x && c.x <= xmax && ymin <= c.y && c.y <= ymax; };
    if (inside(p) || inside(q)) {
        return true;
    }
    int left = 0;
    int right = 0;
    for (const Coord& c : {Coord{x0, y0}, Coord{x1, y0}, Coord{x0, y1}, Coord{x1, y1}}) {
        const int o = orientation(p, q, c);
        left += o > 0 ? 1 : 0;
        right += o < 0 ? 1 : 0;
    }
    return left < 4 && right < 4;
}

// Decided by orientation signs only: an upward segment is crossed right of p when p lies to its
// left, a downward one when p lies to its right.
RayStep ray_step(const Coord& a, const Coord& b, const Coord& p)
{
    if (on_segment(a, b, p)) {
        return RayStep::on_segment;
    }
    if ((a.y > p.y) == (b.y > p.y)) {
        return RayStep::misses;
    }
    const int side = orientation(a, b, p);
    return ((b.y > a.y) ? side > 0 : side < 0) ? RayStep::crosses : RayStep::misses;
}

int locate_in_ring(const std::vector<Coord>& ring, const Coord& p)
{
    const std::size_t n = ring.size();
    bool inside = false;
    for (std::size_t i = 0; i < n; ++i) {
        const RayStep step = ray_step(ring[i], ring[(i + 1) % n], p);
        if (step == RayStep::on_segment) {
            return 0;
        }
        inside ^= step == RayStep::crosses;
    }
    return inside ? 1 : -1;
}

} // namespace trisnap
