#include "assess/str_tree.hpp"

#include <cmath>
#include <numeric>

namespace trisnap::assess {
namespace {

/// Sort-Tile-Recursive order of `ids` by their boxes' centres: vertical slices by x, each by y.
template <class BoxOf>
void str_order(std::vector<std::uint32_t>& ids, BoxOf&& box_of, std::uint32_t fanout)
{
    const std::size_t n = ids.size();
    const auto cx = [&](std::uint32_t i) { return box_of(i).centre().x; };
    const auto cy = [&](std::uint32_t i) { return box_of(i).centre().y; };
    std::sort(ids.begin(), ids.end(), [&](auto a, auto b) { return cx(a) < cx(b) || (cx(a) == cx(b) && a < b); });
    const std::size_t leaves = (n + fanout - 1) / fanout;
    const std::size_t slices = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(leaves))));
    const std::size_t per_slice = slices * fanout;
    for (std::size_t s = 0; s < n; s += per_slice) {
        const auto end = ids.begin() + static_cast<std::ptrdiff_t>(std::min(n, s + per_slice));
        std::sort(ids.begin() + static_cast<std::ptrdiff_t>(s), end,
                  [&](auto a, auto b) { return cy(a) < cy(b) || (cy(a) == cy(b) && a < b); });
    }
}

} // namespace

void StrTree::build(std::vector<Box> boxes)
{
    m_boxes = std::move(boxes);
    m_nodes.clear();
    m_items.resize(m_boxes.size());
    std::iota(m_items.begin(), m_items.end(), 0u);
    if (m_boxes.empty()) {
        return;
    }
    str_order(m_items, [&](std::uint32_t i) -> const Box& { return m_boxes[i]; }, k_fanout);
    for (std::uint32_t i = 0; i < m_items.size(); i += k_fanout) {
        Node leaf{{}, i, std::min<std::uint32_t>(k_fanout, static_cast<std::uint32_t>(m_items.size()) - i), true};
        for (std::uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k) {
            leaf.box.add(m_boxes[m_items[k]]);
        }
        m_nodes.push_back(leaf);
    }
    std::uint32_t level_begin = 0, level_end = static_cast<std::uint32_t>(m_nodes.size());
    while (level_end - level_begin > 1) {
        // Reorder this level's nodes in place (nobody points at them yet), then group them.
        std::vector<std::uint32_t> ids(level_end - level_begin);
        std::iota(ids.begin(), ids.end(), level_begin);
        str_order(ids, [&](std::uint32_t i) -> const Box& { return m_nodes[i].box; }, k_fanout);
        std::vector<Node> reordered;
        reordered.reserve(ids.size());
        for (std::uint32_t id : ids) {
            reordered.push_back(m_nodes[id]);
        }
        std::copy(reordered.begin(), reordered.end(), m_nodes.begin() + level_begin);
        for (std::uint32_t i = level_begin; i < level_end; i += k_fanout) {
            Node parent{{}, i, std::min(k_fanout, level_end - i), false};
            for (std::uint32_t k = parent.first; k < parent.first + parent.count; ++k) {
                parent.box.add(m_nodes[k].box);
            }
            m_nodes.push_back(parent);
        }
        level_begin = level_end;
        level_end = static_cast<std::uint32_t>(m_nodes.size());
    }
    m_root = level_begin;
}

} // namespace trisnap::assess
