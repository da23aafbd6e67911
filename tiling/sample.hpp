#pragma once
// A bounded sample of the input vertices for the tile plan, the same whatever order they come
// in: a vertex is kept when the top `level` bits of a hash of its coordinates are zero, and the
// level goes up by one (halving the sample) whenever the sample outgrows its cap. The sample
// is then a function of the multiset of vertices alone, and each kept vertex stands for about
// 2^level input vertices. With every vertex kept (level 0) the plan is exactly the in-memory
// plan (median k-d tree of all vertices).
#include "tiling/plan.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace trisnap::tiling {

class VertexSample {
public:
    /// `cap`: most vertices kept at once (16 bytes each).
    explicit VertexSample(std::size_t cap) : m_cap(cap < 16 ? 16 : cap) {}
    void add(double x, double y);
    /// Takes in `later`'s vertices (same cap) as if they had been added here after these: the
    /// same level, extent, count and kept vertices in the same order (the level is the least
    /// at which everything added fits the cap, whoever added it).
    void append(VertexSample&& later);
    /// The extent and count of everything added, and the sample.
    PlanInput take();

private:
    bool kept(double x, double y) const;
    /// Drops from (xs, ys) the vertices the current level does not keep.
    void keep_kept(std::vector<double>& xs, std::vector<double>& ys) const;

    std::size_t m_cap;
    int m_level = 0;
    Box m_extent;
    std::size_t m_vertices = 0;
    std::vector<double> m_xs;
    std::vector<double> m_ys;
};

} // namespace trisnap::tiling
