#include "stitch/layout.hpp"

#include <algorithm>
#include <limits>

namespace trisnap::stitch {
namespace {

void put_box(tiling::ByteWriter& w, const tiling::Box& b)
{
    for (double v : {b.xmin, b.ymin, b.xmax, b.ymax}) {
        w.put(v);
    }
}

tiling::Box get_box(tiling::ByteReader& r)
{
    tiling::Box b;
    b.xmin = r.get<double>();
    b.ymin = r.get<double>();
    b.xmax = r.get<double>();
    b.ymax = r.get<double>();
    return b;
}

void put_list(tiling::ByteWriter& w, const std::vector<std::size_t>& v)
{
    w.put<std::uint32_t>(static_cast<std::uint32_t>(v.size()));
    for (std::size_t x : v) {
        w.put<std::uint64_t>(x);
    }
}

std::vector<std::size_t> get_list(tiling::ByteReader& r)
{
    std::vector<std::size_t> v(r.get_count(sizeof(std::uint64_t)));
    for (std::size_t& x : v) {
        x = r.get<std::uint64_t>();
    }
    return v;
}

} // namespace

void TileLayout::save(tiling::ByteWriter& w) const
{
    plan.save(w);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(reach.size()));
    for (std::size_t k = 0; k < reach.size(); ++k) {
        put_box(w, reach[k]);
        w.put<std::uint64_t>(bucket_vertices[k]);
        w.put<std::uint64_t>(bucket_features[k]);
    }
    w.put(halo);
    w.put(seam_band);
}

TileLayout TileLayout::load(tiling::ByteReader& r)
{
    TileLayout l;
    l.plan = tiling::TilePlan::load(r);
    const std::uint32_t n = r.get_count(48);
    for (std::uint32_t k = 0; k < n; ++k) {
        l.reach.push_back(get_box(r));
        l.bucket_vertices.push_back(r.get<std::uint64_t>());
        l.bucket_features.push_back(r.get<std::uint64_t>());
    }
    l.halo = r.get<double>();
    l.seam_band = r.get<double>();
    return l;
}

Groups Groups::of_layout(const TileLayout& layout)
{
    Groups g;
    const std::size_t n = layout.plan.size();
    for (std::size_t leaf = 0; leaf < n; ++leaf) {
        g.of_leaf.push_back(leaf);
        g.leaves.push_back({leaf});
        g.halo.push_back(layout.halo);
        g.runs.push_back(0);
    }
    return g;
}

std::vector<std::size_t> Groups::live(const TileLayout& layout) const
{
    std::vector<std::size_t> out;
    for (std::size_t g = 0; g < leaves.size(); ++g) {
        if (std::any_of(leaves[g].begin(), leaves[g].end(), [&](std::size_t leaf) { return layout.bucket_features[leaf] > 0; })) {
            out.push_back(g);
        }
    }
    return out;
}

void Groups::save(tiling::ByteWriter& w) const
{
    put_list(w, of_leaf);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(leaves.size()));
    for (std::size_t g = 0; g < leaves.size(); ++g) {
        put_list(w, leaves[g]);
        w.put(halo[g]);
        w.put<std::uint32_t>(runs[g]);
    }
    w.put<std::uint64_t>(seam_merges);
}

Groups Groups::load(tiling::ByteReader& r)
{
    Groups g;
    g.of_leaf = get_list(r);
    const std::uint32_t n = r.get_count(sizeof(std::uint32_t));
    for (std::uint32_t k = 0; k < n; ++k) {
        g.leaves.push_back(get_list(r));
        g.halo.push_back(r.get<double>());
        g.runs.push_back(r.get<std::uint32_t>());
    }
    g.seam_merges = r.get<std::uint64_t>();
    return g;
}

tiling::Box group_core(const TileLayout& layout, const Groups& groups, std::size_t group)
{
    tiling::Box b;
    for (std::size_t leaf : groups.leaves[group]) {
        b.add(layout.core_box(leaf));
    }
    return b;
}

Region group_region(const TileLayout& layout, const Groups& groups, std::size_t group)
{
    constexpr double inf = std::numeric_limits<double>::infinity();
    Region region{inf, inf, -inf, -inf};
    for (std::size_t leaf : groups.leaves[group]) {
        const Region& r = layout.plan.core(leaf);
        region.xmin = std::min(region.xmin, r.xmin);
        region.ymin = std::min(region.ymin, r.ymin);
        region.xmax = std::max(region.xmax, r.xmax);
        region.ymax = std::max(region.ymax, r.ymax);
    }
    return region;
}

} // namespace trisnap::stitch
