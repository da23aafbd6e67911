#include "checker_grid.hpp"

#include <limits>

namespace trisnap::checker_detail {

double point_segment_distance(double px, double py, const Segment& s) {
    const double dx = s.bx - s.ax, dy = s.by - s.ay;
    const double len2 = dx * dx + dy * dy;
    double u = len2 > 0.0 ? ((px - s.ax) * dx + (py - s.ay) * dy) / len2 : 0.0;
    u = std::clamp(u, 0.0, 1.0);
    return std::hypot(px - (s.ax + u * dx), py - (s.ay + u * dy));
}

namespace {

/// Length of a segment, DBL_MAX when it overflows (coordinates near +-1e308).
double clamped_length(const Segment& s) {
    return std::min(std::hypot(s.bx - s.ax, s.by - s.ay), std::numeric_limits<double>::max());
}

} // namespace

SegmentGrid::SegmentGrid(const std::vector<Segment>& segments, double min_cell)
    : m_segments(segments), m_seen(segments.size(), 0) {
    if (segments.empty())
        return;
    choose_cell(min_cell);
    for (std::uint32_t i = 0; i < segments.size(); ++i)
        file_segment(i);
    std::sort(m_entries.begin(), m_entries.end());
    m_entries.erase(std::unique(m_entries.begin(), m_entries.end()), m_entries.end());
}

// The cell is the larger of: the query radius, the median segment length (so a typical segment
// is one piece), and what keeps the cell count within 2^31 per axis and the piece count within
// a budget (a few enormous segments must not blow up memory; they only make cells coarser).
void SegmentGrid::choose_cell(double min_cell) {
    m_x0 = m_y0 = std::numeric_limits<double>::infinity();
    m_x1 = m_y1 = -m_x0;
    std::vector<double> lengths;
    lengths.reserve(m_segments.size());
    for (const Segment& s : m_segments) {
        m_x0 = std::min({m_x0, s.ax, s.bx});
        m_y0 = std::min({m_y0, s.ay, s.by});
        m_x1 = std::max({m_x1, s.ax, s.bx});
        m_y1 = std::max({m_y1, s.ay, s.by});
        lengths.push_back(clamped_length(s));
    }
    auto median = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
    std::nth_element(lengths.begin(), median, lengths.end());
    const double half_extent = std::max(m_x1 / 2 - m_x0 / 2, m_y1 / 2 - m_y0 / 2); // cannot overflow
    m_cell = std::max({min_cell, *median, half_extent / 1073741824.0});
    if (!(m_cell > 0.0))
        m_cell = 1.0;
    auto pieces = [&] {
        double n = 0.0;
        for (double len : lengths)
            n += std::ceil(len / m_cell) + 1.0;
        return n;
    };
    while (pieces() > 16.0 * static_cast<double>(lengths.size()) + 4096.0)
        m_cell *= 2.0;
    m_nx = cell_x(m_x1) + 1;
    m_ny = cell_y(m_y1) + 1;
}

void SegmentGrid::file_segment(std::uint32_t index) {
    const Segment& s = m_segments[index];
    const double len = clamped_length(s);
    const auto n = static_cast<std::int64_t>(std::max(1.0, std::ceil(len / m_cell)));
    // Pieces are computed in floating point: widen their boxes a hair so that rounding at a
    // piece boundary cannot leave a cell of the true segment out.
    const double eps = m_cell * 1e-9;
    for (std::int64_t k = 0; k < n; ++k) {
        const double u0 = static_cast<double>(k) / static_cast<double>(n);
        const double u1 = k + 1 == n ? 1.0 : static_cast<double>(k + 1) / static_cast<double>(n);
        // std::lerp: exact at the ends and no overflow of bx - ax.
        const double x0 = std::lerp(s.ax, s.bx, u0), y0 = std::lerp(s.ay, s.by, u0);
        const double x1 = k + 1 == n ? s.bx : std::lerp(s.ax, s.bx, u1);
        const double y1 = k + 1 == n ? s.by : std::lerp(s.ay, s.by, u1);
        const std::int64_t cx0 = std::max<std::int64_t>(0, cell_x(std::min(x0, x1) - eps));
        const std::int64_t cx1 = std::min(m_nx - 1, cell_x(std::max(x0, x1) + eps));
        const std::int64_t cy0 = std::max<std::int64_t>(0, cell_y(std::min(y0, y1) - eps));
        const std::int64_t cy1 = std::min(m_ny - 1, cell_y(std::max(y0, y1) + eps));
        for (std::int64_t cx = cx0; cx <= cx1; ++cx)
            for (std::int64_t cy = cy0; cy <= cy1; ++cy)
                m_entries.emplace_back(key(cx, cy), index);
    }
}

std::uint32_t SegmentGrid::next_stamp() const {
    if (++m_stamp == 0) {
        std::fill(m_seen.begin(), m_seen.end(), 0);
        m_stamp = 1;
    }
    return m_stamp;
}

Nearest SegmentGrid::nearest_in_range(double x, double y, std::size_t begin, std::size_t end,
                                      double start_radius) const {
    const double count = static_cast<double>(end - begin);
    auto offer = [&](Nearest& best, std::size_t i) {
        const double d = point_segment_distance(x, y, m_segments[i]);
        if (d < best.distance)
            best = Nearest{d, i};
    };
    for (double r = start_radius; begin < end; r *= 4.0) {
        const double side = 2.0 * r / m_cell + 2.0;
        if (side * side > 4.0 * count)
            break;
        Nearest best{std::numeric_limits<double>::infinity(), begin};
        visit_near(x, y, r, [&](std::uint32_t i) {
            if (i >= begin && i < end)
                offer(best, i);
        });
        if (best.distance <= r)
            return best;
    }
    Nearest best{std::numeric_limits<double>::infinity(), begin};
    for (std::size_t i = begin; i < end; ++i)
        offer(best, i);
    return best;
}

} // namespace trisnap::checker_detail
