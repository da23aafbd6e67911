#pragma once
// A uniform grid over segments for fixed-radius queries. Long segments are cut into pieces no
// longer than a cell, and each piece is filed under the cells its bounding box touches, so a
// segment thousands of t long costs a few entries per cell it crosses instead of one huge box
// that every nearby vertex would have to test.
#include "checker_geos.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace trisnap::checker_detail {

double point_segment_distance(double px, double py, const Segment& s);

struct Nearest {
    double distance;
    std::size_t index; ///< of the nearest segment; meaningless when distance is +infinity
};

class SegmentGrid {
public:
    /// Cells are at least `min_cell` wide (and wider when the extent or the segment lengths
    /// call for it). Zero-length segments are points: the same grid indexes vertices.
    SegmentGrid(const std::vector<Segment>& segments, double min_cell);

    /// Calls visit(index) once for every segment that may lie within `r` of (x, y), and for
    /// no segment that is further than r + one cell diagonal.
    template <class Visit> void visit_near(double x, double y, double r, Visit&& visit) const;

    /// Distance from (x, y) to the nearest of segments [begin, end): grid rings that widen by
    /// 4x, and a plain scan once the ring would cover more cells than there are segments.
    Nearest nearest_in_range(double x, double y, std::size_t begin, std::size_t end,
                             double start_radius) const;

private:
    // (x/2 - x0/2) / (cell/2): the difference of coordinates near +-1e308 would overflow, and so
    // would x / cell for a huge x at a tiny cell (both found by fuzz_snap). The quotient is
    // clamped before the cast; within the extent it stays below 2^31 (cell >= half extent / 2^30).
    static std::int64_t cell_of(double v, double v0, double cell) {
        const double q = std::floor((v / 2 - v0 / 2) / (cell / 2));
        return static_cast<std::int64_t>(std::clamp(q, -1.0, 4294967296.0));
    }
    std::int64_t cell_x(double x) const { return cell_of(x, m_x0, m_cell); }
    std::int64_t cell_y(double y) const { return cell_of(y, m_y0, m_cell); }
    static std::uint64_t key(std::int64_t cx, std::int64_t cy) {
        return (static_cast<std::uint64_t>(cx) << 32) | static_cast<std::uint64_t>(cy);
    }
    void choose_cell(double min_cell);
    void file_segment(std::uint32_t index);
    std::uint32_t next_stamp() const;

    const std::vector<Segment>& m_segments;
    double m_x0 = 0.0, m_y0 = 0.0, m_x1 = 0.0, m_y1 = 0.0;
    double m_cell = 1.0;
    std::int64_t m_nx = 1, m_ny = 1;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> m_entries; ///< sorted (cell, segment)
    mutable std::vector<std::uint32_t> m_seen; ///< query stamp per segment, to report it once
    mutable std::uint32_t m_stamp = 0;
};

template <class Visit> void SegmentGrid::visit_near(double x, double y, double r, Visit&& visit) const {
    if (m_entries.empty() || x + r < m_x0 || y + r < m_y0 || x - r > m_x1 || y - r > m_y1)
        return;
    const std::uint32_t stamp = next_stamp();
    const std::int64_t cx0 = std::max<std::int64_t>(0, cell_x(x - r));
    const std::int64_t cx1 = std::min<std::int64_t>(m_nx - 1, cell_x(x + r));
    const std::int64_t cy0 = std::max<std::int64_t>(0, cell_y(y - r));
    const std::int64_t cy1 = std::min<std::int64_t>(m_ny - 1, cell_y(y + r));
    for (std::int64_t cx = cx0; cx <= cx1; ++cx) {
        for (std::int64_t cy = cy0; cy <= cy1; ++cy) {
            auto it = std::lower_bound(m_entries.begin(), m_entries.end(),
                                       std::make_pair(key(cx, cy), std::uint32_t{0}));
            for (; it != m_entries.end() && it->first == key(cx, cy); ++it) {
                if (m_seen[it->second] == stamp)
                    continue;
                m_seen[it->second] = stamp;
                visit(it->second);
            }
        }
    }
}

} // namespace trisnap::checker_detail
