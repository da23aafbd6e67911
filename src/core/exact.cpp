// Exact constructions rounded once (see exact.hpp): GMP rationals from the stored doubles, then
// the nearest double of each coordinate.
#include "core/exact.hpp"

#include <CGAL/Gmpq.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace trisnap::detail {
namespace {

using Q = CGAL::Gmpq;

// mpq_get_d truncates towards zero; the nearest double is that one or its neighbour away from
// zero, whichever is closer to q, the even one on a tie.
double nearest_double(const Q& q)
{
    const double toward = q.to_double();
    if (Q(toward) == q) {
        return toward;
    }
    const double inf = std::numeric_limits<double>::infinity();
    const double away = std::nextafter(toward, q > Q(0) ? inf : -inf);
    const Q mid = (Q(toward) + Q(away)) / Q(2);
    const bool toward_is_above = toward > away;
    if (q > mid) {
        return toward_is_above ? toward : away;
    }
    if (q < mid) {
        return toward_is_above ? away : toward;
    }
    return (std::bit_cast<std::uint64_t>(toward) & 1u) == 0 ? toward : away;
}

Q cross(const Q& ax, const Q& ay, const Q& bx, const Q& by) { return ax * by - ay * bx; }

} // namespace

cdt::Point rounded_crossing(const cdt::Point& a, const cdt::Point& b, const cdt::Point& c,
                            const cdt::Point& d)
{
    const Q ax(a.x()), ay(a.y());
    const Q abx = Q(b.x()) - ax, aby = Q(b.y()) - ay;
    const Q cdx = Q(d.x()) - Q(c.x()), cdy = Q(d.y()) - Q(c.y());
    const Q acx = Q(c.x()) - ax, acy = Q(c.y()) - ay;
    // a + s (b - a) lies on c-d where s = (c - a) x (d - c) / ((b - a) x (d - c)).
    const Q s = cross(acx, acy, cdx, cdy) / cross(abx, aby, cdx, cdy);
    return cdt::Point(nearest_double(ax + s * abx), nearest_double(ay + s * aby));
}

bool within_ulps(const cdt::Point& p, const cdt::Point& q, int k)
{
    auto ulp = [](double v) {
        const double a = std::abs(v);
        return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
    };
    return std::abs(p.x() - q.x()) <= k * ulp(q.x()) && std::abs(p.y() - q.y()) <= k * ulp(q.y());
}

bool within_ulps_of_segment(const cdt::Point& p, const cdt::Point& s0, const cdt::Point& s1, int k)
{
    const double m = std::max(std::abs(p.x()), std::abs(p.y()));
    const double ulp = std::nextafter(m, std::numeric_limits<double>::infinity()) - m;
    const Q limit = Q(k * ulp) * Q(k * ulp);
    const Q px(p.x()), py(p.y()), ax(s0.x()), ay(s0.y());
    const Q dx = Q(s1.x()) - ax, dy = Q(s1.y()) - ay;
    const Q apx = px - ax, apy = py - ay;
    const Q along = apx * dx + apy * dy;
    const Q len2 = dx * dx + dy * dy;
    if (along <= 0 || len2 == 0) {
        return apx * apx + apy * apy <= limit;
    }
    if (along >= len2) {
        const Q bpx = px - Q(s1.x()), bpy = py - Q(s1.y());
        return bpx * bpx + bpy * bpy <= limit;
    }
    const Q c = cross(apx, apy, dx, dy);
    return c * c <= limit * len2;
}

cdt::Point rounded_projection(const cdt::Point& p, const cdt::Point& b, const cdt::Point& c)
{
    const Q bx(b.x()), by(b.y());
    const Q dx = Q(c.x()) - bx, dy = Q(c.y()) - by;
    const Q s = ((Q(p.x()) - bx) * dx + (Q(p.y()) - by) * dy) / (dx * dx + dy * dy);
    return cdt::Point(nearest_double(bx + s * dx), nearest_double(by + s * dy));
}

} // namespace trisnap::detail
