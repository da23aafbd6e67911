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
        for (const Path& r : p.rings) b.add(box_of(r));
    for (const Path& l : g.lines) b.add(box_of(l));
    return b;
}

Box box_of(const std::vector<Coord>& path)
{
    if (path.empty()) return {};
    Box b{path[0].x, path[0].y, path[0].x, path[0].y};
    for (const Coord& c : path) {
        b.xmin = std::min(b.xmin, c.x), b.xmax = std::max(b.xmax, c.x);
        b.ymin = std::min(b.ymin, c.y), b.ymax = std::max(b.ymax, c.y);
    }
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
    m_node_of_leaf.push_back(static_cast<int>(m_nodes.size() - 1));
    return static_cast<int>(m_nodes.size() - 1);
}

std::size_t TilePlan::split_leaf(std::size_t leaf, int axis, double value)
{
    const auto node = static_cast<std::size_t>(m_node_of_leaf[leaf]);
    Region lower = m_cores[leaf];
    Region upper = lower;
    (axis == 0 ? lower.xmax : lower.ymax) = value;
    (axis == 0 ? upper.xmin : upper.ymin) = value;
    m_cores[leaf] = lower;
    const int left = static_cast<int>(m_nodes.size());
    m_nodes.push_back(Node{-1, 0, -1, -1, leaf});
    m_node_of_leaf[leaf] = left;
    const std::size_t added = m_cores.size();
    const int right = add_leaf(upper);
    m_nodes[node] = Node{axis, value, left, right, 0};
    if (m_leaf_vertices.size() == added) {
        m_leaf_vertices.push_back(0);
    }
    return added;
}

void TilePlan::save(ByteWriter& w) const
{
    w.put<std::uint32_t>(static_cast<std::uint32_t>(m_nodes.size()));
    for (const Node& n : m_nodes) {
        w.put<std::int32_t>(n.axis);
        w.put(n.split);
        w.put<std::int32_t>(n.left);
        w.put<std::int32_t>(n.right);
        w.put<std::uint64_t>(n.leaf);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(m_cores.size()));
    for (std::size_t k = 0; k < m_cores.size(); ++k) {
        const Region& c = m_cores[k];
        for (double v : {c.xmin, c.ymin, c.xmax, c.ymax}) {
            w.put(v);
        }
        w.put<std::int32_t>(m_node_of_leaf[k]);
        w.put<std::uint64_t>(k < m_leaf_vertices.size() ? m_leaf_vertices[k] : 0);
    }
    for (double v : {m_extent.xmin, m_extent.ymin, m_extent.xmax, m_extent.ymax}) {
        w.put(v);
    }
    w.put<std::uint64_t>(m_vertices);
}

TilePlan TilePlan::load(ByteReader& r)
{
    TilePlan plan;
    plan.m_nodes.resize(r.get_count(28));
    for (Node& n : plan.m_nodes) {
        n.axis = r.get<std::int32_t>();
        n.split = r.get<double>();
        n.left = r.get<std::int32_t>();
        n.right = r.get<std::int32_t>();
        n.leaf = r.get<std::uint64_t>();
    }
    const std::uint32_t leaves = r.get_count(48);
    for (std::uint32_t k = 0; k < leaves; ++k) {
        Region c;
        c.xmin = r.get<double>();
        c.ymin = r.get<double>();
        c.xmax = r.get<double>();
        c.ymax = r.get<double>();
        plan.m_cores.push_back(c);
        plan.m_node_of_leaf.push_back(r.get<std::int32_t>());
        plan.m_leaf_vertices.push_back(r.get<std::uint64_t>());
    }
    plan.m_extent.xmin = r.get<double>();
    plan.m_extent.ymin = r.get<double>();
    plan.m_extent.xmax = r.get<double>();
    plan.m_extent.ymax = r.get<double>();
    plan.m_vertices = r.get<std::uint64_t>();
    return plan;
}

// Median split of the longer side of the vertices' box; the median value does not depend on
// the order of the input, so neither does the plan.
int TilePlan::build_balanced(std::vector<double>& xs, std::vector<double>& ys, std::vector<double>& scratch,
                             std::size_t lo, std::size_t hi, const Region& r, std::size_t budget, double halo, int depth)
{
    if (hi - lo <= budget || depth > 40) return add_leaf(r);
    Box b;
    for (std::size_t i = lo; i < hi; ++i) b.add(xs[i], ys[i]);
    const int axis = b.width() >= b.height() ? 0 : 1;
    std::vector<double>& key = axis == 0 ? xs : ys;
    std::vector<double>& other = axis == 0 ? ys : xs;
    const std::size_t mid = lo + (hi - lo) / 2;
    // The median of a copy (one buffer for the whole tree), so that the pairs stay together.
    scratch.assign(key.begin() + static_cast<std::ptrdiff_t>(lo), key.begin() + static_cast<std::ptrdiff_t>(hi));
    std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(mid - lo), scratch.end());
    const double split = scratch[mid - lo];
    if (!(split > (axis == 0 ? b.xmin : b.ymin))) return add_leaf(r); // all on one coordinate
    if (halo > 0) {
        // Each half with the other's vertices within the halo of the cut (PlanOptions::halo).
        std::size_t lower = 0, lower_band = 0, upper_band = 0;
        for (std::size_t i = lo; i < hi; ++i) {
            if (key[i] < split) {
                ++lower;
                lower_band += key[i] >= split - halo ? 1 : 0;
            } else {
                upper_band += key[i] < split + halo ? 1 : 0;
            }
        }
        const std::size_t n = hi - lo;
        if (4 * std::max(lower + upper_band, n - lower + lower_band) > 3 * n) return add_leaf(r);
    }
    // Partition both arrays by key < split, keeping pairs together.
    std::size_t m = lo;
    for (std::size_t i = lo; i < hi; ++i)
        if (key[i] < split) { std::swap(key[i], key[m]); std::swap(other[i], other[m]); ++m; }
    Region left = r, right = r;
    (axis == 0 ? left.xmax : left.ymax) = split;
    (axis == 0 ? right.xmin : right.ymin) = split;
    const int self = static_cast<int>(m_nodes.size());
    m_nodes.push_back(Node{axis, split, -1, -1, 0});
    const int l = build_balanced(xs, ys, scratch, lo, m, left, budget, halo, depth + 1);
    const int rr = build_balanced(xs, ys, scratch, m, hi, right, budget, halo, depth + 1);
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

// The balanced plan is built on the sample with the budget scaled to it: with every vertex in
// the sample (level 0) it is the exact median k-d tree of the input vertices.
TilePlan make_plan(PlanInput input, const PlanOptions& options)
{
    TilePlan plan;
    plan.m_extent = input.extent;
    plan.m_vertices = input.vertices;
    const Region everything;
    if (options.single || plan.m_extent.empty()) {
        plan.add_leaf(everything);
    } else if (options.tile_size > 0) {
        const double s = options.tile_size;
        const double ox = std::floor(plan.m_extent.xmin / s) * s;
        const double oy = std::floor(plan.m_extent.ymin / s) * s;
        const double cols = std::max(1.0, std::ceil((plan.m_extent.xmax - ox) / s + 1e-12));
        const double rows = std::max(1.0, std::ceil((plan.m_extent.ymax - oy) / s + 1e-12));
        if (!(cols * rows <= 1e6)) {
            throw std::invalid_argument("tile size " + std::to_string(s) + " would make " + std::to_string(cols * rows) +
                                        " tiles (more than 10^6); choose a larger --tile-size");
        }
        plan.build_grid(0, static_cast<long>(cols), 0, static_cast<long>(rows), everything, s, ox, oy);
    } else {
        const std::size_t budget = std::max<std::size_t>(options.vertex_budget, 16) >> input.level;
        std::vector<double> scratch;
        scratch.reserve(input.xs.size());
        plan.build_balanced(input.xs, input.ys, scratch, 0, input.xs.size(), everything, std::max<std::size_t>(budget, 1),
                             options.halo, 0);
    }
    plan.m_leaf_vertices.assign(plan.size(), 0);
    return plan;
}

TilePlan make_plan(const std::vector<Feature>& features, const PlanOptions& options)
{
    PlanInput input;
    auto for_each_vertex = [&](auto&& visit) {
        for (const Feature& f : features) {
            for (const Polygon& p : f.geometry.polygons) {
                for (const Path& r : p.rings) {
                    std::for_each(r.begin(), r.end(), visit);
                }
            }
            std::for_each(f.geometry.lines.begin(), f.geometry.lines.end(),
                          [&](const Path& l) { std::for_each(l.begin(), l.end(), visit); });
        }
    };
    for_each_vertex([&](const Coord& c) {
        if (std::isfinite(c.x) && std::isfinite(c.y)) {
            input.extent.add(c.x, c.y);
            ++input.vertices;
            input.xs.push_back(c.x);
            input.ys.push_back(c.y);
        }
    });
    TilePlan plan = make_plan(std::move(input), options);
    std::vector<std::size_t> counts(plan.size(), 0);
    for_each_vertex([&](const Coord& c) {
        if (std::isfinite(c.x) && std::isfinite(c.y)) {
            ++counts[plan.leaf_of(c.x, c.y)];
        }
    });
    plan.set_leaf_vertices(std::move(counts));
    return plan;
}

} // namespace trisnap::tiling
