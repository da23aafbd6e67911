#pragma once
// A uniform grid over segments or points, stored as one sorted array of (cell, item) entries:
// no hashing, so memory is two words per entry and iteration order is deterministic. A segment
// is entered in the cells its thin band crosses (a walk column by column), not its whole
// bounding box, so long diagonal segments cost O(length / cell).
#include "render/types.hpp"

#include <cstdint>
#include <vector>

namespace trisnap::render {

struct Segment {
    XY a;
    XY b;
};

class GridIndex {
public:
    /// Indexes segments; `cell` > 0 in layer units.
    GridIndex(const std::vector<Segment>& segments, double cell);
    /// Indexes points (one cell each).
    GridIndex(const std::vector<XY>& points, double cell);

    /// Calls f(item) for every item entered in a cell that meets the box around p of half-size
    /// r; an item may be visited more than once. Items farther than r may be visited too.
    template <class F>
    void visit(XY p, double r, F&& f) const
    {
        const std::int64_t x0 = cell_of(p.x - r), x1 = cell_of(p.x + r);
        const std::int64_t y0 = cell_of(p.y - r), y1 = cell_of(p.y + r);
        for (std::int64_t ix = x0; ix <= x1; ++ix)
            for (std::int64_t iy = y0; iy <= y1; ++iy)
                for (std::size_t i = lower_bound(ix, iy); i < m_entries.size() && m_entries[i].ix == ix &&
                                                           m_entries[i].iy == iy; ++i)
                    f(m_entries[i].item);
    }

    double cell() const { return m_cell; }

    /// A cell size for segments: the mean segment length, at least `min_cell`, so a segment
    /// spans few cells and a query of radius min_cell touches few cells.
    static double cell_for(const std::vector<Segment>& segments, double min_cell);

private:
    struct Entry {
        std::int64_t ix;
        std::int64_t iy;
        std::uint32_t item;
    };
    std::int64_t cell_of(double v) const;
    std::size_t lower_bound(std::int64_t ix, std::int64_t iy) const;
    void add_segment(const Segment& s, std::uint32_t item);
    void finish();

    double m_cell;
    std::vector<Entry> m_entries;
};

} // namespace trisnap::render
