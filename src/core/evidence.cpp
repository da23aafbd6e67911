#include "core/evidence.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <tuple>

namespace trisnap::detail {
namespace {

Coord midpoint(const Mesh& mesh, std::uint32_t u, std::uint32_t v)
{
    const Xy a = mesh.xy(u);
    const Xy b = mesh.xy(v);
    return Coord{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
}

// Vertices inside an input edge of a polygon feature: (vertex, feature, owner).
using Inside = std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>>;

// A vertex inside two input edges of one polygon feature: two straight edges through one
// interior point either cross there or overlap.
void flag_shared_interior(const Mesh& mesh, const Region& region, Inside& inside, std::vector<bool>& flag)
{
    std::sort(inside.begin(), inside.end());
    inside.erase(std::unique(inside.begin(), inside.end()), inside.end());
    for (std::size_t k = 1; k < inside.size(); ++k) {
        const auto [x, feature, owner] = inside[k];
        if (x != std::get<0>(inside[k - 1]) || feature != std::get<1>(inside[k - 1])) {
            continue;
        }
        if (region.contains(mesh.xy(x).x, mesh.xy(x).y)) {
            flag[feature] = true;
        }
    }
}

} // namespace

// One pass over the owner table: a sub-edge owned twice or more by one polygon feature means
// two of its edges overlap there.
std::vector<bool> self_intersecting(const Mesh& mesh, std::size_t features, const Region& region)
{
    std::vector<bool> flag(features, false);
    Inside inside;
    std::vector<FeatureCount> counts;
    mesh.for_each_edge_with_owners([&](std::uint32_t u, std::uint32_t v, std::span<const OwnerRef> refs) {
        for (const OwnerRef& ref : refs) {
            const Owner& o = mesh.owner_at(ref.owner);
            if (o.line) {
                continue;
            }
            const std::uint32_t from = mesh.owner_from(o), to = mesh.owner_to(o);
            for (const std::uint32_t x : {u, v}) {
                if (x != from && x != to) {
                    inside.emplace_back(x, o.feature, ref.owner);
                }
            }
        }
        mesh.polygon_ownership(refs, counts);
        for (const FeatureCount& c : counts) {
            if (c.times < 2) {
                continue;
            }
            const Coord m = midpoint(mesh, u, v);
            if (region.contains(m.x, m.y)) {
                flag[c.feature] = true;
            }
        }
    });
    flag_shared_interior(mesh, region, inside, flag);
    return flag;
}

std::vector<double> edge_deviation(const Mesh& mesh, std::size_t features, const Region& region)
{
    std::vector<double> worst(features, 0.0);
    mesh.for_each_owned_edge([&](std::uint32_t u, std::uint32_t v, OwnerRef ref) {
        const Owner& o = mesh.owner_at(ref.owner);
        // An end of the input edge, still an input point, is exactly that end: distance 0, which
        // cannot raise the maximum. Most pieces are whole input edges: nearly all stop here.
        const std::uint32_t from = mesh.owner_from(o), to = mesh.owner_to(o);
        const auto at_own_end = [&](std::uint32_t x) { return (x == from || x == to) && mesh.is_input_point(x); };
        if (at_own_end(u) && at_own_end(v)) {
            return;
        }
        // The input edge itself: its ends' records keep the input points (an edit removes a
        // vertex and inserts another; it never moves one).
        const Xy a = mesh.xy(from);
        const Xy b = mesh.xy(to);
        for (const std::uint32_t x : {u, v}) {
            if (at_own_end(x)) {
                // It is one of the segment's ends (its distance is 0; distance_point_segment can
                // give an ulp for the far end, a + 1 * (b - a) rounding away from b, which the
                // assert here claimed was 0 and a debug build's Grid test showed was not).
                assert((mesh.xy(x).x == a.x && mesh.xy(x).y == a.y) || (mesh.xy(x).x == b.x && mesh.xy(x).y == b.y));
                continue;
            }
            const Xy r = mesh.xy(x);
            if (region.contains(r.x, r.y)) {
                worst[o.feature] = std::max(worst[o.feature], distance_point_segment(r.x, r.y, a.x, a.y, b.x, b.y));
            }
        }
    });
    return worst;
}

CollapsedEdges collapsed_edges(const Mesh& mesh, const Region& region)
{
    // A piece of a polygon's input edge has the same membership on both sides exactly when the
    // polygon owns it an even number of times: labels are crossing parities (labelling.cpp), and
    // each polygon's pieces form closed chains, so the parity does not depend on the path. That
    // is read from the owner table; only an edge with such a piece is checked against the
    // triangulation (an owned pair that is no constrained edge of it bounds nothing). Every piece
    // is kept, then each feature's are summed and the smallest midpoint taken: neither depends on
    // the table's order.
    CollapsedEdges out;
    std::vector<CollapsedEdge>& pieces = out.found;
    std::vector<FeatureCount> counts;
    mesh.for_each_edge_with_owners([&](std::uint32_t u, std::uint32_t v, std::span<const OwnerRef> refs) {
        mesh.polygon_ownership(refs, counts);
        int is_edge = -1; // not asked yet
        for (const FeatureCount& c : counts) {
            if (c.times % 2 == 1) {
                continue;
            }
            if (is_edge < 0) {
                is_edge = mesh.is_triangulation_constraint(u, v) ? 1 : 0;
            }
            const Coord mid = midpoint(mesh, u, v);
            if (is_edge == 0 || !region.contains(mid.x, mid.y)) {
                continue;
            }
            pieces.push_back(CollapsedEdge{c.feature, c.times, mid});
        }
    });
    std::sort(pieces.begin(), pieces.end(), [](const CollapsedEdge& a, const CollapsedEdge& b) {
        return std::tie(a.feature, a.where.x, a.where.y) < std::tie(b.feature, b.where.x, b.where.y);
    });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        if (kept > 0 && pieces[kept - 1].feature == pieces[k].feature) {
            pieces[kept - 1].count += pieces[k].count; // the first of a feature's has the smallest midpoint
        } else {
            pieces[kept++] = pieces[k];
        }
    }
    pieces.resize(kept);
    pieces.shrink_to_fit();
    return out;
}

void report_collapsed_edges(const CollapsedEdges& found, const std::vector<Outline>& clean,
                            const std::vector<bool>& written, std::vector<Problem>& problems)
{
    for (const CollapsedEdge& e : found.found) {
        if (!written[e.feature]) {
            continue;
        }
        problems.push_back(Problem{clean[e.feature].id, ProblemCode::thin_part_collapsed,
            // No count of the pieces: a tile counts only those in its core, and the report must
            // read the same whatever the tiling (the stitch keeps one 209 per feature).
            "input edges no longer bound the polygon from here on: a part thinner than the tolerance collapsed",
            e.where.x, e.where.y});
    }
}

void report_unresolved(Mesh& mesh, const SnapperOutcome& outcome, const std::vector<Outline>& clean,
                       const Region& region, double grid, std::vector<Problem>& problems)
{
    const ProblemCode code = outcome.converged ? ProblemCode::separation_not_reached : ProblemCode::not_converged;
    std::vector<std::uint32_t> owners;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> hits; // feature, vertex
    auto& tri = mesh.tri();
    for (std::uint32_t v : outcome.unresolved) {
        if (!region.contains(mesh.xy(v).x, mesh.xy(v).y)) {
            continue;
        }
        auto vc = tri.incident_vertices(mesh.handle(v));
        const auto done = vc;
        do {
            if (tri.is_infinite(vc)) {
                continue;
            }
            mesh.owners_of_edge(v, vc->info().id, owners);
            for (std::uint32_t o : owners) {
                hits.emplace_back(mesh.owner_at(o).feature, v);
            }
        } while (++vc != done);
    }
    std::sort(hits.begin(), hits.end());
    for (std::size_t k = 0; k < hits.size(); ++k) {
        if (k > 0 && hits[k].first == hits[k - 1].first) {
            continue;
        }
        const Xy r = mesh.xy(hits[k].second);
        problems.push_back(Problem{clean[hits[k].first].id, code,
            std::string(outcome.converged ? "a vertex stays closer than the tolerance allows (a split refused because it already "
                                            "snapped into that edge, or a merge blocked by a constraint)"
                                          : "operation cap reached before the fix-point") +
                (grid > 0 ? "; the output of this run is not rounded to the grid (rounding could make it invalid)" : ""),
            r.x, r.y});
    }
}

} // namespace trisnap::detail
