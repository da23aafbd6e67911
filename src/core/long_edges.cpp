#include "core/long_edges.hpp"

#include <algorithm>
#include <cmath>

namespace trisnap::detail {
namespace {

// Cell indexes stay below 2^52 in magnitude: floor() of the quotient is then an exact integer.
constexpr double k_range = 4503599627370496.0; // 2^52

} // namespace

void LongEdgeIndex::reset(double radius2)
{
    m_radius2 = radius2;
    m_radius = std::sqrt(radius2);
    m_side = 2 * m_radius;
    m_cells.clear();
    m_entries = 0;
}

bool LongEdgeIndex::cell_of(double x, double y, std::int64_t& cx, std::int64_t& cy) const
{
    const double qx = std::floor(x / m_side);
    const double qy = std::floor(y / m_side);
    if (!(std::abs(qx) < k_range) || !(std::abs(qy) < k_range)) { // also NaN, and a side of 0
        return false;
    }
    cx = static_cast<std::int64_t>(qx);
    cy = static_cast<std::int64_t>(qy);
    return true;
}

bool LongEdgeIndex::cells(double ax, double ay, double bx, double by, std::vector<std::uint64_t>& out) const
{
    out.clear();
    const double r = m_radius;
    // Far above the rounding of the quotients and of the segment's y at a column's ends (a few
    // ulps of the coordinates and of the edge's extent).
    const double eps = 1e-9 * m_side + 1e-12 * (std::abs(ax) + std::abs(ay) + std::abs(bx) + std::abs(by));
    const double minx = std::min(ax, bx), maxx = std::max(ax, bx);
    const double miny = std::min(ay, by), maxy = std::max(ay, by);
    std::int64_t c0 = 0, c1 = 0, unused = 0;
    if (!cell_of(minx - r - eps, miny, c0, unused) || !cell_of(maxx + r + eps, maxy, c1, unused)) {
        return false;
    }
    std::size_t count = 0;
    for (std::int64_t c = c0; c <= c1; ++c) {
        // The part of the segment whose points can be within r of a point of this column.
        const double lo = std::max(minx, static_cast<double>(c) * m_side - r - eps);
        const double hi = std::min(maxx, static_cast<double>(c + 1) * m_side + r + eps);
        double ylo = miny, yhi = maxy;
        if (bx != ax && lo <= hi) {
            const double k = (by - ay) / (bx - ax);
            const double y1 = ay + (lo - ax) * k;
            const double y2 = ay + (hi - ax) * k;
            ylo = std::clamp(std::min(y1, y2), miny, maxy);
            yhi = std::clamp(std::max(y1, y2), miny, maxy);
        }
        std::int64_t r0 = 0, r1 = 0;
        if (!cell_of(0.0, ylo - r - eps, unused, r0) || !cell_of(0.0, yhi + r + eps, unused, r1)) {
            return false;
        }
        count += static_cast<std::size_t>(r1 - r0 + 1);
        if (count > max_cells) {
            return false;
        }
        for (std::int64_t row = r0; row <= r1; ++row) {
            out.push_back(cell_key(c, row));
        }
    }
    // Hashed keys of two cells may coincide: each list holds the edge once.
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return true;
}

bool LongEdgeIndex::insert(double ax, double ay, double bx, double by, std::uint64_t key)
{
    if (!cells(ax, ay, bx, by, m_scratch)) {
        return false;
    }
    for (const std::uint64_t cell : m_scratch) {
        m_cells[cell].push_back(key);
    }
    m_entries += m_scratch.size();
    return true;
}

bool LongEdgeIndex::erase(double ax, double ay, double bx, double by, std::uint64_t key)
{
    if (!cells(ax, ay, bx, by, m_scratch)) {
        return false;
    }
    for (const std::uint64_t cell : m_scratch) {
        const auto it = m_cells.find(cell);
        if (it == m_cells.end()) {
            continue;
        }
        std::vector<std::uint64_t>& list = it->second;
        const auto at = std::find(list.begin(), list.end(), key);
        if (at != list.end()) {
            *at = list.back();
            list.pop_back();
            --m_entries;
        }
        if (list.empty()) {
            m_cells.erase(it);
        }
    }
    return true;
}

} // namespace trisnap::detail
