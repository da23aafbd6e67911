#include "tiling/plan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace trisnap::tiling {

void Box::add(double x, double y)
{
    if (empty()) { *this = {x, y, x, y}; return; }
    xmin = std::min(xmin, x), ymin = std::min(ymin, y), xmax = std::max(xmax, x), ymax = std::max(ymax, y);
}

void Box::add(const Box& b)
{
    if (b.empty()) return;
    add(b.xmin, b.ymin);
    add(b.xmax, b.ymax);
}

Box box_of(const Geometry& g)
{
    Box b;
    for (const Polygon& p : g.polygons)
        for (const Path& r : p.rings)
            for (const Coord& c : r) b.add(c.x, c.y);
    for (const Path& l : g.lines)
        for (const Coord& c : l) b.add(c.x, c.y);
    return b;
}

Box clip(const Region& r, const Box& e)
{
    return {std::max(r.xmin, e.xmin), std::max(r.ymin, e.ymin), std::min(r.xmax, e.xmax), std::min(r.ymax, e.ymax)};
}

std::size_t TilePlan::leaf_of(double x, double y) const
{
    int n = 0;
    while (m_nodes[static_cast<std::size_t>(n)].axis >= 0) {
        const Node& node = m_nodes[static_cast<std::size_t>(n)];
        n = (node.axis == 0 ? x : y) < node.split ? node.left : node.right;
    }
    return m_nodes[static_cast<std::size_t>(n)].leaf;
}

void TilePlan::query(const Box& b, std::vector<std::size_t>& out) const
{
    const std::size_t first = out.size();
    query(0, b, out);
    std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

void TilePlan::query(int n, const Box& b, std::vector<std::size_t>& out) const
{
    const Node& node = m_nodes[static_cast<std::size_t>(n)];
    if (node.axis < 0) { out.push_back(node.leaf); return; }
    const double lo = node.axis == 0 ? b.xmin : b.ymin, hi = node.axis == 0 ? b.xmax : b.ymax;
    if (lo < node.split) query(node.left, b, out);
    if (hi >= node.split) query(node.right, b, out);
}

int TilePlan::add_leaf(const Region& r)
{
    Node leaf;
    leaf.leaf = m_cores.size();
    m_cores.push_back(r);
    m_nodes.push_back(leaf);
    return static_cast<int>(m_nodes.size() - 1);
}

// Median split of the longer side of the vertices' box; the median value does not depend on
// the order of the input, so neither does the plan.
int TilePlan::build_balanced(std::vector<double>& xs, std::vector<double>& ys, std::size_t lo, std::size_t hi,
                             const Region& r, std::size_t budget, int depth)
{
    if (hi - lo <= budget || depth > 40) return add_leaf(r);
    Box b;
    for (std::size_t i = lo; i < hi; ++i) b.add(xs[i], ys[i]);
    const int axis = b.width() >= b.height() ? 0 : 1;
    std::vector<double>& key = axis == 0 ? xs : ys;
    std::vector<double>& other = axis == 0 ? ys : xs;
    const std::size_t mid = lo + (hi - lo) / 2;
    std::vector<double> tmp(key.begin() + static_cast<std::ptrdiff_t>(lo), key.begin() + static_cast<std::ptrdiff_t>(hi));
    std::nth_element(tmp.begin(), tmp.begin() + static_cast<std::ptrdiff_t>(mid - lo), tmp.end());
    const double split = tmp[mid - lo];
    if (!(split > (axis == 0 ? b.xmin : b.ymin))) return add_leaf(r); // all on one coordinate
    // Partition both arrays by key < split, keeping pairs together.
    std::size_t m = lo;
    for (std::size_t i = lo; i < hi; ++i)
        if (key[i] < split) { std::swap(key[i], key[m]); std::swap(other[i], other[m]); ++m; }
    Region left = r, right = r;
    (axis == 0 ? left.xmax : left.ymax) = split;
    (axis == 0 ? right.xmin : right.ymin) = split;
    const int self = static_cast<int>(m_nodes.size());
    m_nodes.push_back(Node{axis, split, -1, -1, 0});
    const int l = build_balanced(xs, ys, lo, m, left, budget, depth + 1);
    const int rr = build_balanced(xs, ys, m, hi, right, budget, depth + 1);
    m_nodes[static_cast<std::size_t>(self)].left = l;
    m_nodes[static_cast<std::size_t>(self)].right = rr;
    return self;
}

// Columns [c0, c1) and rows [r0, r1) of the grid; the outer ones reach infinity.
int TilePlan::build_grid(long c0, long c1, long r0, long r1, const Region& r, double size, double ox, double oy)
{
    if (c1 - c0 == 1 && r1 - r0 == 1) return add_leaf(r);
    const bool by_x = (c1 - c0) >= (r1 - r0);
    const long mid = by_x ? (c0 + c1) / 2 : (r0 + r1) / 2;
    const double split = by_x ? ox + static_cast<double>(mid) * size : oy + static_cast<double>(mid) * size;
    Region left = r, right = r;
    (by_x ? left.xmax : left.ymax) = split;
    (by_x ? right.xmin : right.ymin) = split;
    const int self = static_cast<int>(m_nodes.size());
    m_nodes.push_back(Node{by_x ? 0 : 1, split, -1, -1, 0});
    const int l = by_x ? build_grid(c0, mid, r0, r1, left, size, ox, oy) : build_grid(c0, c1, r0, mid, left, size, ox, oy);
    const int rr = by_x ? build_grid(mid, c1, r0, r1, right, size, ox, oy) : build_grid(c0, c1, mid, r1, right, size, ox, oy);
    m_nodes[static_cast<std::size_t>(self)].left = l;
    m_nodes[static_cast<std::size_t>(self)].right = rr;
    return self;
}

TilePlan make_plan(const std::vector<Feature>& features, const PlanOptions& options)
{
    TilePlan plan;
    std::vector<double> xs, ys;
    auto for_each_vertex = [&](auto&& visit) {
        for (const Feature& f : features) {
            for (const Polygon& p : f.geometry.polygons)
                for (const Path& r : p.rings)
                    for (const Coord& c : r)
                        if (std::isfinite(c.x) && std::isfinite(c.y)) visit(c);
            for (const Path& l : f.geometry.lines)
                for (const Coord& c : l)
                    if (std::isfinite(c.x) && std::isfinite(c.y)) visit(c);
        }
    };
    for_each_vertex([&](const Coord& c) {
        plan.m_extent.add(c.x, c.y);
        ++plan.m_vertices;
        if (!options.single && options.tile_size <= 0) xs.push_back(c.x), ys.push_back(c.y);
    });
    const Region everything;
    if (options.single || plan.m_extent.empty()) {
        plan.add_leaf(everything);
    } else if (options.tile_size > 0) {
        const double s = options.tile_size;
        const double ox = std::floor(plan.m_extent.xmin / s) * s, oy = std::floor(plan.m_extent.ymin / s) * s;
        const double cols = std::max(1.0, std::ceil((plan.m_extent.xmax - ox) / s + 1e-12));
        const double rows = std::max(1.0, std::ceil((plan.m_extent.ymax - oy) / s + 1e-12));
        if (cols * rows > 1e6)
            throw std::invalid_argument("tile size " + std::to_string(s) + " would make " + std::to_string(cols * rows) +
                                        " tiles (more than 10^6); choose a larger --tile-size");
        plan.build_grid(0, static_cast<long>(cols), 0, static_cast<long>(rows), everything, s, ox, oy);
    } else {
        plan.build_balanced(xs, ys, 0, xs.size(), everything, std::max<std::size_t>(options.vertex_budget, 16), 0);
    }
    plan.m_leaf_vertices.assign(plan.size(), 0);
    for_each_vertex([&](const Coord& c) { ++plan.m_leaf_vertices[plan.leaf_of(c.x, c.y)]; });
    return plan;
}

} // namespace trisnap::tiling
