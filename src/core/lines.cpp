// Line features: their constraints' sub-edges, chained back into linestrings by the assembler.
#include "core/extraction.hpp"

namespace trisnap::detail {

// Two passes over the owner table, counting then placing: each feature's edges in the table's
// order, as one vector per feature had them.
LineEdges collect_line_edges(Mesh& mesh, std::size_t feature_count)
{
    LineEdges out;
    mesh.for_each_owned_edge([&](std::uint32_t, std::uint32_t, OwnerRef ref) {
        const Owner& o = mesh.owner_at(ref.owner);
        if (o.line) {
            if (out.first.empty()) out.first.assign(feature_count + 1, 0);
            ++out.first[o.feature + 1];
        }
    });
    if (out.first.empty()) {
        return out;
    }
    for (std::size_t f = 0; f < feature_count; ++f) {
        out.first[f + 1] += out.first[f];
    }
    out.edges.resize(out.first.back());
    // first[f] serves as feature f's next place while filling, which leaves it at first[f + 1];
    // shifting the table one place back then gives the starts again.
    mesh.for_each_owned_edge([&](std::uint32_t u, std::uint32_t v, OwnerRef ref) {
        const Owner& o = mesh.owner_at(ref.owner);
        if (o.line) {
            out.edges[out.first[o.feature]++] = ref.forward ? IdEdge{u, v} : IdEdge{v, u};
        }
    });
    std::copy_backward(out.first.begin(), out.first.end() - 1, out.first.end());
    out.first[0] = 0;
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
