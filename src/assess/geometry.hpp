#pragma once
// Plain geometry for the assessor: points, boxes, exact orientation and segment predicates,
// distances. Independent of src/core on purpose: assess judges the engine, it must not share
// its arithmetic. Orientation is exact for all finite doubles (a floating-point filter, then an
// exact expansion sum, after Shewchuk 1997; exact rationals for coordinates beyond 2^+-400), so
// "touches", "collinear" and "same vertex" are decided exactly on the stored doubles; distances
// are plain double arithmetic (measurements, not decisions).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace trisnap::assess {

constexpr double k_inf = std::numeric_limits<double>::infinity();

struct Pt {
    double x = 0;
    double y = 0;
};
inline bool operator==(Pt a, Pt b) { return a.x == b.x && a.y == b.y; }
inline bool operator!=(Pt a, Pt b) { return !(a == b); }
inline bool operator<(Pt a, Pt b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

struct Box {
    double xmin = k_inf, ymin = k_inf, xmax = -k_inf, ymax = -k_inf;
    void add(Pt p)
    {
        xmin = std::min(xmin, p.x);
        ymin = std::min(ymin, p.y);
        xmax = std::max(xmax, p.x);
        ymax = std::max(ymax, p.y);
    }
    void add(const Box& b)
    {
        xmin = std::min(xmin, b.xmin);
        ymin = std::min(ymin, b.ymin);
        xmax = std::max(xmax, b.xmax);
        ymax = std::max(ymax, b.ymax);
    }
    bool empty() const { return xmin > xmax; }
    /// Closed boxes: touching boxes intersect.
    bool intersects(const Box& b) const
    {
        return xmin <= b.xmax && b.xmin <= xmax && ymin <= b.ymax && b.ymin <= ymax;
    }
    /// The intersection has positive area (interiors meet).
    bool overlaps(const Box& b) const { return xmin < b.xmax && b.xmin < xmax && ymin < b.ymax && b.ymin < ymax; }
    Box intersection(const Box& b) const
    {
        return {std::max(xmin, b.xmin), std::max(ymin, b.ymin), std::min(xmax, b.xmax), std::min(ymax, b.ymax)};
    }
    double distance(Pt p) const
    {
        const double dx = std::max({xmin - p.x, 0.0, p.x - xmax});
        const double dy = std::max({ymin - p.y, 0.0, p.y - ymax});
        return std::sqrt(dx * dx + dy * dy);
    }
    Pt centre() const { return {0.5 * (xmin + xmax), 0.5 * (ymin + ymax)}; }
};

inline Box segment_box(Pt a, Pt b)
{
    Box box;
    box.add(a);
    box.add(b);
    return box;
}

/// +1 when c is left of a->b, -1 right, 0 collinear; exact for finite doubles.
int orient(Pt a, Pt b, Pt c);

enum class SegmentContact { none, shared_endpoint, identical, crossing };

/// How two closed segments meet: not at all; only at an endpoint they both have (exact equal
/// coordinates); identical (same two endpoints); or anywhere else ("crossing": a proper crossing,
/// an endpoint touching the other's interior, or a collinear overlap). `where` gets a point of the
/// contact for crossings.
SegmentContact segment_contact(Pt p1, Pt q1, Pt p2, Pt q2, Pt* where = nullptr);

/// Distance from p to the closed segment a-b, and the closest point.
double point_segment_distance(Pt p, Pt a, Pt b, Pt* closest = nullptr);

/// Length of the collinear overlap of two segments (0 unless exactly collinear).
double collinear_overlap(Pt p1, Pt q1, Pt p2, Pt q2);

inline double distance(Pt a, Pt b)
{
    const double dx = a.x - b.x, dy = a.y - b.y;
    return std::sqrt(dx * dx + dy * dy);
}

} // namespace trisnap::assess
