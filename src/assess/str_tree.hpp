#pragma once
// A static R-tree packed with Sort-Tile-Recursive (Leutenegger, Lopez, Edgington 1997): boxes
// in, ids 0..n-1 out. Box queries and nearest-item queries (depth-first, children visited
// nearest first, pruned by the best distance so far). Read-only after build, so any number of
// threads may query it at once. Robust to clustered data and long segments, unlike a uniform grid.
#include "assess/geometry.hpp"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace trisnap::assess {

class StrTree {
public:
    StrTree() = default;
    explicit StrTree(std::vector<Box> boxes) { build(std::move(boxes)); }
    void build(std::vector<Box> boxes);
    std::size_t size() const { return m_boxes.size(); }
    const Box& box(std::uint32_t id) const { return m_boxes[id]; }

    /// Calls f(id) for every item whose box intersects `query` (closed boxes).
    template <class F>
    void query(const Box& query, F&& f) const
    {
        if (m_nodes.empty()) {
            return;
        }
        // Depth-first: at most fanout entries per level on the stack, and depth < 16.
        std::array<std::uint32_t, k_fanout * 16> stack;
        std::size_t top = 0;
        stack[top++] = m_root;
        while (top > 0) {
            const Node& node = m_nodes[stack[--top]];
            if (!node.box.intersects(query)) {
                continue;
            }
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                if (!node.leaf) {
                    stack[top++] = i;
                } else if (m_boxes[m_items[i]].intersects(query)) {
                    f(m_items[i]);
                }
            }
        }
    }

    /// The item nearest to p by `dist(id)` (an exact distance, k_inf to exclude an item), among
    /// items closer than `bound`. Returns {id, distance}, or {UINT32_MAX, bound} when none.
    template <class D>
    std::pair<std::uint32_t, double> nearest(Pt p, D&& dist, double bound = k_inf) const
    {
        std::pair<std::uint32_t, double> best{UINT32_MAX, bound};
        if (!m_nodes.empty()) {
            nearest_in(m_root, p, dist, best);
        }
        return best;
    }

private:
    struct Node {
        Box box;
        std::uint32_t first = 0; // children: nodes (inner) or positions in m_items (leaf)
        std::uint32_t count = 0;
        bool leaf = false;
    };
    static constexpr std::uint32_t k_fanout = 16;

    template <class D>
    void nearest_in(std::uint32_t index, Pt p, D& dist, std::pair<std::uint32_t, double>& best) const
    {
        const Node& node = m_nodes[index];
        if (node.leaf) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                const std::uint32_t id = m_items[i];
                if (m_boxes[id].distance(p) >= best.second) {
                    continue;
                }
                const double d = dist(id);
                if (d < best.second) {
                    best = {id, d};
                }
            }
            return;
        }
        std::array<std::pair<double, std::uint32_t>, k_fanout> order;
        std::uint32_t n = 0;
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
            order[n++] = {m_nodes[i].box.distance(p), i};
        }
        std::sort(order.begin(), order.begin() + n);
        for (std::uint32_t k = 0; k < n && order[k].first < best.second; ++k) {
            nearest_in(order[k].second, p, dist, best);
        }
    }

    std::vector<Box> m_boxes;
    std::vector<std::uint32_t> m_items;
    std::vector<Node> m_nodes;
    std::uint32_t m_root = 0;
};

} // namespace trisnap::assess
