#include "render/grid_index.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace trisnap::render {

GridIndex::GridIndex(const std::vector<Segment>& segments, double cell) : m_cell(cell)
{
    if (!(cell > 0)) throw std::invalid_argument("grid cell must be > 0");
    m_entries.reserve(segments.size() * 2);
    for (std::size_t i = 0; i < segments.size(); ++i) add_segment(segments[i], static_cast<std::uint32_t>(i));
    finish();
}

GridIndex::GridIndex(const std::vector<XY>& points, double cell) : m_cell(cell)
{
    if (!(cell > 0)) throw std::invalid_argument("grid cell must be > 0");
    m_entries.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        m_entries.push_back({cell_of(points[i].x), cell_of(points[i].y), static_cast<std::uint32_t>(i)});
    finish();
}

double GridIndex::cell_for(const std::vector<Segment>& segments, double min_cell)
{
    double total = 0;
    for (const Segment& s : segments) total += distance(s.a, s.b);
    const double mean = segments.empty() ? 0.0 : total / static_cast<double>(segments.size());
    return std::max(mean, min_cell);
}

std::int64_t GridIndex::cell_of(double v) const
{
    // Clamped so far-off coordinates at a tiny cell cannot overflow; they share edge cells.
    const double c = std::floor(v / m_cell);
    return static_cast<std::int64_t>(std::clamp(c, -4e18, 4e18));
}

std::size_t GridIndex::lower_bound(std::int64_t ix, std::int64_t iy) const
{
    auto it = std::lower_bound(m_entries.begin(), m_entries.end(), std::pair{ix, iy},
                               [](const Entry& e, const std::pair<std::int64_t, std::int64_t>& k) {
                                   return e.ix < k.first || (e.ix == k.first && e.iy < k.second);
                               });
    return static_cast<std::size_t>(it - m_entries.begin());
}

void GridIndex::add_segment(const Segment& s, std::uint32_t item)
{
    XY a = s.a, b = s.b;
    if (b.x < a.x) std::swap(a, b);
    const std::int64_t x0 = cell_of(a.x), x1 = cell_of(b.x);
    const double slope = b.x > a.x ? (b.y - a.y) / (b.x - a.x) : 0.0;
    for (std::int64_t ix = x0; ix <= x1; ++ix) {
        // The y range of the segment inside this column.
        const double cx0 = std::max(a.x, static_cast<double>(ix) * m_cell);
        const double cx1 = std::min(b.x, static_cast<double>(ix + 1) * m_cell);
        double ya = a.y + slope * (cx0 - a.x), yb = a.y + slope * (cx1 - a.x);
        if (x0 == x1) ya = a.y, yb = b.y;
        const double slack = m_cell * 1e-9; // rounding must not drop a cell the segment touches
        const std::int64_t y0 = cell_of(std::min(ya, yb) - slack), y1 = cell_of(std::max(ya, yb) + slack);
        for (std::int64_t iy = y0; iy <= y1; ++iy) m_entries.push_back({ix, iy, item});
    }
}

void GridIndex::finish()
{
    std::sort(m_entries.begin(), m_entries.end(), [](const Entry& a, const Entry& b) {
        if (a.ix != b.ix) return a.ix < b.ix;
        if (a.iy != b.iy) return a.iy < b.iy;
        return a.item < b.item;
    });
}

} // namespace trisnap::render
