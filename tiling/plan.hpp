#pragma once
// The tile plan: the plane cut into half-open core rectangles (a k-d tree, so a point has
// exactly one owner), each snapped with a halo of width h around it.
//  - balanced: split the longer side at the median vertex until a tile holds <= budget vertices;
//  - regular: a grid of side `tile_size` (anchored at multiples of it);
//  - single: one tile (the plane).
// Outer tiles extend to infinity, so every point of the plane has an owner.
#include "core/geometry.hpp"
#include "core/snap.hpp"
#include "tiling/binary_io.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace trisnap::tiling {

/// A closed box; empty when xmin > xmax.
struct Box {
    double xmin = 0, ymin = 0, xmax = -1, ymax = -1;
    bool empty() const { return xmin > xmax || ymin > ymax; }
    bool intersects(const Box& o) const { return !(o.xmin > xmax || o.xmax < xmin || o.ymin > ymax || o.ymax < ymin); }
    bool contains(const Box& o) const { return xmin <= o.xmin && o.xmax <= xmax && ymin <= o.ymin && o.ymax <= ymax; }
    Box expanded(double d) const { return {xmin - d, ymin - d, xmax + d, ymax + d}; }
    void add(double x, double y);
    void add(const Box& b);
    double width() const { return xmax - xmin; }
    double height() const { return ymax - ymin; }
};
Box box_of(const Geometry& g);
/// The box of a path's points (empty for no points).
Box box_of(const std::vector<Coord>& path);
/// The finite part of a region clipped to `extent` (closed).
Box clip(const Region& r, const Box& extent);

/// What a plan is made from: the extent and number of the input vertices, and a sample of
/// them (every vertex when `level` is 0; else each sampled vertex stands for 2^level vertices,
/// see tiling/sample.hpp).
struct PlanInput {
    Box extent;
    std::size_t vertices = 0;
    std::vector<double> xs;
    std::vector<double> ys;
    int level = 0;

    /// Frees the sampled vertices once the plan is made (the extent and counts stay). Not
    /// `xs = {}`: that assigns an empty initializer list and keeps the capacity (up to 256 MiB).
    void drop_sample()
    {
        std::vector<double>().swap(xs);
        std::vector<double>().swap(ys);
    }
    /// The sample with its vertices moved out of this one (which keeps its extent and counts):
    /// the plan takes them without a copy (up to 256 MiB each).
    PlanInput take_vertices()
    {
        PlanInput out{extent, vertices, std::move(xs), std::move(ys), level};
        drop_sample();
        return out;
    }
};

struct PlanOptions {
    /// Balanced plan: a tile is split while it holds more than this many input vertices.
    std::size_t vertex_budget = 50000;
    /// > 0: a regular grid of this side (layer units) instead of the balanced plan.
    double tile_size = 0.0;
    /// One tile (`--no-tiles`).
    bool single = false;
    /// Balanced plan: the halo width (layer units) the tiles will be snapped with. A cut is not
    /// made when a half would hold more than 3/4 of the tile's vertices with the other half's
    /// vertices within `halo` of the cut (its halo): at a tolerance near the features' size that
    /// band is most of the tile, and cutting only copies it (NJ shore at 0.003 degrees: 8 tiles
    /// held 3.7 times the layer and the run took 3.4 times the untiled one). 0: cut by count only
    /// (make_buckets() plans so under a memory limit, whose tiles must fit their budget).
    double halo = 0.0;
};

class TilePlan {
public:
    std::size_t size() const { return m_cores.size(); }
    const Region& core(std::size_t leaf) const { return m_cores[leaf]; }
    /// The leaf whose half-open core holds (x, y).
    std::size_t leaf_of(double x, double y) const;
    /// Leaves whose core meets the closed box `b` (appended, ascending).
    void query(const Box& b, std::vector<std::size_t>& out) const;
    /// Extent of the input (closed box of every vertex).
    const Box& extent() const { return m_extent; }
    std::size_t input_vertices() const { return m_vertices; }
    /// Input vertices whose point the leaf's core holds (counted by whoever made the plan).
    std::size_t leaf_vertices(std::size_t leaf) const { return m_leaf_vertices[leaf]; }
    void set_leaf_vertices(std::vector<std::size_t> counts) { m_leaf_vertices = std::move(counts); }
    /// Splits a leaf's core at `value` on `axis` (0: x, 1: y): the leaf keeps the lower part and
    /// the upper part ([value, ...)) becomes a new leaf, whose id is returned.
    std::size_t split_leaf(std::size_t leaf, int axis, double value);

    void save(ByteWriter& w) const;
    static TilePlan load(ByteReader& r);

    friend TilePlan make_plan(PlanInput input, const PlanOptions& options);

private:
    struct Node {
        int axis = -1;        ///< -1 leaf, 0 split on x, 1 on y
        double split = 0;     ///< left: < split, right: >= split
        int left = -1, right = -1;
        std::size_t leaf = 0;
    };
    int build_balanced(std::vector<double>& xs, std::vector<double>& ys, std::vector<double>& scratch, std::size_t lo,
                       std::size_t hi, const Region& r, std::size_t budget, double halo, int depth);
    int build_grid(long c0, long c1, long r0, long r1, const Region& r, double size, double ox, double oy);
    int add_leaf(const Region& r);
    void query(int node, const Box& b, std::vector<std::size_t>& out) const;

    std::vector<Node> m_nodes;
    std::vector<int> m_node_of_leaf;
    std::vector<Region> m_cores;
    std::vector<std::size_t> m_leaf_vertices;
    Box m_extent;
    std::size_t m_vertices = 0;
};

/// Throws std::invalid_argument when a regular grid would need more than 10^6 tiles. The leaf
/// vertex counts are left at 0.
TilePlan make_plan(PlanInput input, const PlanOptions& options);
/// The plan of a set of features held in memory: every vertex sampled, leaf vertices counted.
TilePlan make_plan(const std::vector<Feature>& features, const PlanOptions& options);

} // namespace trisnap::tiling
