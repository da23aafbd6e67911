// Exact orientation after Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates" (1997): a static filter, then the exact sign of the six-product
// expansion of the determinant. Needs IEEE doubles without fused multiply-add contraction
// (-ffp-contract=off, set for every trisnap target). Both are exact only while no product
// overflows or underflows, so coordinates outside [2^-400, 2^400] go to exact rational
// arithmetic (GMP) instead: tested against CGAL's exact predicates at 1e-300 and 1e300.
#include "assess/geometry.hpp"

#include <gmpxx.h>

#include <array>
#include <initializer_list>

namespace trisnap::assess {
namespace {

void two_sum(double a, double b, double& x, double& y)
{
    x = a + b;
    const double bv = x - a;
    const double av = x - bv;
    y = (a - av) + (b - bv);
}

void split(double a, double& hi, double& lo)
{
    const double c = 134217729.0 * a; // 2^27 + 1
    const double abig = c - a;
    hi = c - abig;
    lo = a - hi;
}

void two_product(double a, double b, double& x, double& y)
{
    x = a * b;
    double ahi, alo, bhi, blo;
    split(a, ahi, alo);
    split(b, bhi, blo);
    const double err1 = x - ahi * bhi;
    const double err2 = err1 - alo * bhi;
    const double err3 = err2 - ahi * blo;
    y = alo * blo - err3;
}

/// Adds b to the nonoverlapping expansion e[0..n) (increasing magnitude), dropping zeros.
int grow_expansion(double* e, int n, double b)
{
    double q = b;
    int out = 0;
    for (int i = 0; i < n; ++i) {
        double sum, err;
        two_sum(q, e[i], sum, err);
        q = sum;
        if (err != 0) {
            e[out++] = err;
        }
    }
    if (q != 0) {
        e[out++] = q;
    }
    return out;
}

int exact_orient(Pt a, Pt b, Pt c)
{
    // det = ax*by - ax*cy - cx*by - ay*bx + ay*cx + cy*bx (the cx*cy terms cancel).
    const std::array<std::array<double, 3>, 6> terms{{{a.x, b.y, 1}, {a.x, c.y, -1}, {c.x, b.y, -1},
                                                      {a.y, b.x, -1}, {a.y, c.x, 1}, {c.y, b.x, 1}}};
    std::array<double, 24> e{};
    int n = 0;
    for (const auto& t : terms) {
        double hi, lo;
        two_product(t[0] * t[2], t[1], hi, lo); // negation is exact
        n = grow_expansion(e.data(), n, lo);
        n = grow_expansion(e.data(), n, hi);
    }
    if (n == 0) {
        return 0;
    }
    return e[n - 1] > 0 ? 1 : -1;
}

/// Every nonzero coordinate within [2^-400, 2^400]: then differences of coordinates are 0 or
/// at least 2^-452, their products and the products of coordinates stay within the normal
/// range (at least 2^-904, at most 2^802), and the filter's and expansions' error analyses hold.
bool in_expansion_range(Pt a, Pt b, Pt c)
{
    for (double v : {a.x, a.y, b.x, b.y, c.x, c.y}) {
        const double m = std::abs(v);
        if (m != 0 && !(m >= 0x1p-400 && m <= 0x1p+400)) {
            return false;
        }
    }
    return true;
}

/// The sign of the determinant in exact rationals (a double converts exactly).
int rational_orient(Pt a, Pt b, Pt c)
{
    const mpq_class ax(a.x), ay(a.y), bx(b.x), by(b.y), cx(c.x), cy(c.y);
    const mpq_class det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx);
    return sgn(det);
}

} // namespace

int orient(Pt a, Pt b, Pt c)
{
    if (!in_expansion_range(a, b, c)) {
        return rational_orient(a, b, c);
    }
    const double detleft = (a.x - c.x) * (b.y - c.y);
    const double detright = (a.y - c.y) * (b.x - c.x);
    const double det = detleft - detright;
    double detsum;
    if (detleft > 0) {
        if (detright <= 0) {
            return det > 0 ? 1 : (det < 0 ? -1 : 0);
        }
        detsum = detleft + detright;
    } else if (detleft < 0) {
        if (detright >= 0) {
            return det > 0 ? 1 : (det < 0 ? -1 : 0);
        }
        detsum = -detleft - detright;
    } else {
        return det > 0 ? 1 : (det < 0 ? -1 : 0);
    }
    const double bound = 3.3306690738754716e-16 * detsum;
    if (det > bound) {
        return 1;
    }
    if (-det > bound) {
        return -1;
    }
    return exact_orient(a, b, c);
}

namespace {

SegmentContact collinear_contact(Pt p1, Pt q1, Pt p2, Pt q2, Pt* where)
{
    // Points of one line are ordered lexicographically along it.
    const Pt lo1 = std::min(p1, q1), hi1 = std::max(p1, q1);
    const Pt lo2 = std::min(p2, q2), hi2 = std::max(p2, q2);
    const Pt lo = std::max(lo1, lo2), hi = std::min(hi1, hi2);
    if (hi < lo) {
        return SegmentContact::none;
    }
    if (lo == hi) {
        const bool end1 = lo == p1 || lo == q1, end2 = lo == p2 || lo == q2;
        if (end1 && end2) {
            return SegmentContact::shared_endpoint;
        }
        if (where) {
            *where = lo;
        }
        return SegmentContact::crossing;
    }
    if (lo1 == lo2 && hi1 == hi2) {
        return SegmentContact::identical;
    }
    if (where) {
        *where = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)};
    }
    return SegmentContact::crossing;
}

} // namespace

SegmentContact segment_contact(Pt p1, Pt q1, Pt p2, Pt q2, Pt* where)
{
    if (!segment_box(p1, q1).intersects(segment_box(p2, q2))) {
        return SegmentContact::none;
    }
    const int o1 = orient(p1, q1, p2), o2 = orient(p1, q1, q2);
    if (o1 * o2 > 0) {
        return SegmentContact::none;
    }
    const int o3 = orient(p2, q2, p1), o4 = orient(p2, q2, q1);
    if (o3 * o4 > 0) {
        return SegmentContact::none;
    }
    if (o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0) {
        return collinear_contact(p1, q1, p2, q2, where);
    }
    // Not collinear: the segments meet in exactly one point.
    if (p1 == p2 || p1 == q2 || q1 == p2 || q1 == q2) {
        return SegmentContact::shared_endpoint;
    }
    if (where) {
        if (o1 == 0) {
            *where = p2;
        } else if (o2 == 0) {
            *where = q2;
        } else if (o3 == 0) {
            *where = p1;
        } else if (o4 == 0) {
            *where = q1;
        } else {
            const double dx1 = q1.x - p1.x, dy1 = q1.y - p1.y, dx2 = q2.x - p2.x, dy2 = q2.y - p2.y;
            const double t = ((p2.x - p1.x) * dy2 - (p2.y - p1.y) * dx2) / (dx1 * dy2 - dy1 * dx2);
            *where = {p1.x + t * dx1, p1.y + t * dy1};
        }
    }
    return SegmentContact::crossing;
}

double point_segment_distance(Pt p, Pt a, Pt b, Pt* closest)
{
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const Pt c = t == 0 ? a : (t == 1 ? b : Pt{a.x + t * dx, a.y + t * dy});
    if (closest) {
        *closest = c;
    }
    return distance(p, c);
}

double collinear_overlap(Pt p1, Pt q1, Pt p2, Pt q2)
{
    if (p1 == q1 || p2 == q2) {
        return 0;
    }
    if (!segment_box(p1, q1).intersects(segment_box(p2, q2))) {
        return 0;
    }
    if (orient(p1, q1, p2) != 0 || orient(p1, q1, q2) != 0) {
        return 0;
    }
    const Pt lo = std::max(std::min(p1, q1), std::min(p2, q2));
    const Pt hi = std::min(std::max(p1, q1), std::max(p2, q2));
    return hi < lo ? 0 : distance(lo, hi);
}

} // namespace trisnap::assess
