// Line features: their constraints' sub-edges, chained back into linestrings in input order.
#include "core/extraction.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace trisnap::detail {

std::vector<std::vector<LineEdge>> collect_line_edges(Mesh& mesh, std::size_t feature_count)
{
    std::vector<std::vector<LineEdge>> out(feature_count);
    auto& tri = mesh.tri();
    for (auto cit = tri.constraints_begin(); cit != tri.constraints_end(); ++cit) {
        const Owner& o = mesh.owner(*cit);
        if (!o.line) continue;
        std::uint32_t order = 0, prev = cdt::k_no_id;
        for (auto it = tri.vertices_in_constraint_begin(*cit); it != tri.vertices_in_constraint_end(*cit); ++it) {
            const std::uint32_t v = (*it)->info().id;
            if (prev != cdt::k_no_id) out[o.feature].push_back(LineEdge{o.part, o.seg, order++, prev, v});
            prev = v;
        }
    }
    // Constraint iteration follows addresses; sort so nothing downstream depends on them.
    for (auto& edges : out)
        std::sort(edges.begin(), edges.end(), [](const LineEdge& a, const LineEdge& b) {
            return std::tie(a.part, a.seg, a.order, a.from, a.to) < std::tie(b.part, b.seg, b.order, b.from, b.to);
        });
    return out;
}

Geometry extract_lines(Mesh& mesh, std::vector<LineEdge> edges,
                       const std::vector<std::uint32_t>& part_starts, const ExtractOptions& options)
{
    Geometry g;
    g.has_z = options.has_z;
    std::vector<bool> used(edges.size(), false);
    std::multimap<std::uint32_t, std::size_t> out_of; // vertex -> edges leaving it, input order
    for (std::size_t k = 0; k < edges.size(); ++k) out_of.emplace(edges[k].from, k);
    auto coord = [&](std::uint32_t v) {
        const VertexRecord& r = mesh.vertex(v);
        Coord c{r.x, r.y, options.has_z ? r.z : std::nan("")};
        if (options.grid > 0) c.x = std::round(c.x / options.grid) * options.grid, c.y = std::round(c.y / options.grid) * options.grid;
        c.x += 0.0, c.y += 0.0; // no negative zeros in the output
        return c;
    };
    auto take = [&](std::uint32_t v, std::uint32_t part) -> std::size_t {
        auto [lo, hi] = out_of.equal_range(v);
        for (auto it = lo; it != hi; ++it)
            if (!used[it->second] && edges[it->second].part == part) return it->second;
        return edges.size();
    };
    auto walk = [&](std::uint32_t v, std::uint32_t part) {
        Path path{coord(v)};
        for (std::size_t k = take(v, part); k < edges.size(); k = take(v, part)) {
            used[k] = true;
            v = edges[k].to;
            path.push_back(coord(v));
        }
        if (path.size() >= 2) g.lines.push_back(std::move(path));
    };
    for (std::uint32_t part = 0; part < part_starts.size(); ++part) walk(part_starts[part], part);
    for (std::size_t k = 0; k < edges.size(); ++k)
        if (!used[k]) walk(edges[k].from, edges[k].part);
    g.type = g.lines.empty() ? Geometry::Type::Empty
           : g.lines.size() == 1 ? Geometry::Type::LineString : Geometry::Type::MultiLineString;
    return g;
}

} // namespace trisnap::detail
