// Line features: their constraints' sub-edges, chained back into linestrings by the assembler.
#include "core/extraction.hpp"

namespace trisnap::detail {

std::vector<std::vector<IdEdge>> collect_line_edges(Mesh& mesh, std::size_t feature_count)
{
    std::vector<std::vector<IdEdge>> out(feature_count);
    mesh.for_each_owned_edge([&](std::uint32_t u, std::uint32_t v, OwnerRef ref) {
        const Owner& o = mesh.owner_at(ref.owner);
        if (o.line) {
            out[o.feature].push_back(ref.forward ? IdEdge{u, v} : IdEdge{v, u});
        }
    });
    return out;
}

// The assembler orders edges itself (exactly, by coordinates), so the order of constraints
// (the owner table's) does not reach the output.
Geometry extract_lines(const Mesh& mesh, std::span<const IdEdge> edges,
                       const std::vector<Coord>& part_starts, const ExtractOptions& options)
{
    std::vector<DirectedEdge> directed = directed_edges(mesh, edges, options);
    std::vector<Coord> starts;
    for (const Coord& s : part_starts) {
        starts.push_back(round_to_grid(s, options.grid));
    }
    return assemble_lines(std::move(directed), starts, options.has_z);
}

} // namespace trisnap::detail
