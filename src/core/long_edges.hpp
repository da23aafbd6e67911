#pragma once
// Where the long constrained edges are (Mesh::set_long_edge_length2): a uniform grid of square
// cells, each listing the long edges whose capsule of radius r (the snapper's edge radius) may
// meet it, so that "which long edges lie within r of p?" looks at p's cell only.
//
// Why: a vertex's nearest-only walk (Mesh::search_point) must reach every long edge within the
// edge radius, because only a long edge can give it a split event. With one long edge anywhere
// in the layer the walk covered the whole disk of that radius around every vertex, and at a
// tolerance near the features' size that disk holds thousands of vertices: NJ shore (one
// polygon of 254 k vertices with a few straight edges along the sea) took 25 s at 0.01 degrees,
// 73 s at 0.03 and 443 s at 0.1. With the grid the walks shrink to the nearest vertex and the
// long edges near the vertex come from its cell: about 10 s at every one of these tolerances
// (4.5-5.5 s since the snapper's queue of 2026-12-02, Snapper::check_face).
//
// An edge goes into every cell its capsule meets, found column by column (the segment's y range
// over the column widened by r, then widened by r and a rounding margin), so a point within r
// of the edge always finds it in its own cell: the test is conservative, never blind. An edge
// that would need more than `max_cells` cells, or whose coordinates are beyond the grid's exact
// range, is not indexed: insert() returns false, and the caller checks it for every vertex. Cell
// keys are hashed (two cells may share a list: more candidates, never fewer). The same edge with
// the same coordinates always gets the same cells, so erase() finds what insert() put.
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace trisnap::detail {

class LongEdgeIndex {
public:
    /// Empties the index for edges of capsule radius sqrt(radius2) (> 0); cells are 2 radii wide.
    void reset(double radius2);
    /// Adds the edge `key` from a to b. False (nothing added): not indexable, see above.
    bool insert(double ax, double ay, double bx, double by, std::uint64_t key);
    /// Removes what insert() with the same arguments added. False when that was nothing.
    bool erase(double ax, double ay, double bx, double by, std::uint64_t key);
    /// Calls f(key) for each edge listed in p's cell (each once): every indexed edge within the
    /// radius of p among them. False, calling nothing, when p lies beyond the grid's range (the
    /// caller must then look at every edge).
    template <class F>
    bool each(double px, double py, F&& f) const
    {
        std::int64_t cx = 0, cy = 0;
        if (!cell_of(px, py, cx, cy)) {
            return false;
        }
        const auto it = m_cells.find(cell_key(cx, cy));
        if (it != m_cells.end()) {
            for (const std::uint64_t key : it->second) {
                f(key);
            }
        }
        return true;
    }
    /// The squared radius it was reset for (exactly).
    double radius2() const { return m_radius2; }
    /// Cell entries held (each edge once per cell it is in).
    std::size_t entries() const { return m_entries; }
    static constexpr std::size_t max_cells = std::size_t{1} << 14;

private:
    bool cell_of(double x, double y, std::int64_t& cx, std::int64_t& cy) const;
    static std::uint64_t cell_key(std::int64_t cx, std::int64_t cy)
    {
        return static_cast<std::uint64_t>(cx) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(cy);
    }
    /// The cells of the edge's capsule, as keys; false when more than max_cells or out of range.
    bool cells(double ax, double ay, double bx, double by, std::vector<std::uint64_t>& out) const;

    double m_radius2 = 0;
    double m_radius = 0;
    double m_side = 0;
    std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> m_cells;
    std::size_t m_entries = 0;
    std::vector<std::uint64_t> m_scratch; ///< insert()'s and erase()'s cells
};

} // namespace trisnap::detail
