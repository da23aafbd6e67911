// Line features: their constraints' sub-edges, chained back into linestrings by the assembler.
#include "core/extraction.hpp"

namespace trisnap::detail {

std::vector<std::vector<LineEdge>> collect_line_edges(Mesh& mesh, std::size_t feature_count)
{
    std::vector<std::vector<LineEdge>> out(feature_count);
    auto& tri = mesh.tri();
    for (auto cit = tri.constraints_begin(); cit != tri.constraints_end(); ++cit) {
        const Owner& o = mesh.owner(*cit);
        if (!o.line) {
            continue;
        }
        std::uint32_t prev = cdt::k_no_id;
        for (auto it = tri.vertices_in_constraint_begin(*cit); it != tri.vertices_in_constraint_end(*cit); ++it) {
            const std::uint32_t v = (*it)->info().id;
            if (prev != cdt::k_no_id) {
                out[o.feature].push_back(LineEdge{prev, v});
            }
            prev = v;
        }
    }
    return out;
}

// The assembler orders edges itself (exactly, by coordinates), so the order of constraints
// (addresses) does not reach the output.
Geometry extract_lines(const Mesh& mesh, const std::vector<LineEdge>& edges,
                       const std::vector<Coord>& part_starts, const ExtractOptions& options)
{
    std::vector<DirectedEdge> directed;
    directed.reserve(edges.size());
    for (const LineEdge& e : edges) {
        directed.push_back(DirectedEdge{output_coord(mesh, e.from, options), output_coord(mesh, e.to, options)});
    }
    std::vector<Coord> starts;
    for (const Coord& s : part_starts) {
        starts.push_back(round_to_grid(s, options.grid));
    }
    return assemble_lines(std::move(directed), starts, options.has_z);
}

} // namespace trisnap::detail
