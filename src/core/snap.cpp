// Snap rounding inside a constrained Delaunay triangulation (after the TU Delft "snap rounding
// polygons with a triangulation" method, with prepair's odd-even labelling):
//   1. clean the input and report repairs (input_cleaning);
//   2. insert every input edge as a constraint, crossings split exactly (mesh_build);
//   3. snap to a fix-point, smallest distance first (snapper);
//   4. label faces with the polygons they lie in (labelling) and trace the output (extraction).
// Guarantees at tolerance t (checked by tests/support, which shares no code with this):
// vertices >= t apart, vertex-edge >= edge_separation*t, OGC-valid polygons, every input feature
// in the output or the problems, shared boundaries kept shared (they are the same sub-edges),
// and the same output whatever the order of the input features.
// With an output grid g the snapper works with margins of 2g on both thresholds; rounding moves
// a vertex by at most g/sqrt(2), so distances shrink by at most sqrt(2)*g < 2g and no vertex
// crosses an edge: the rounded output keeps the contract and stays valid.
#include "core/snap.hpp"

#include "core/extraction.hpp"
#include "core/input_cleaning.hpp"
#include "core/labelling.hpp"
#include "core/mesh.hpp"
#include "core/outcome.hpp"
#include "core/snapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace trisnap {
namespace {

using detail::CleanFeature;
using detail::Mesh;

class Stopwatch {
public:
    double lap()
    {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - m_start).count();
        m_start = now;
        return s;
    }

private:
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

detail::SnapperParams snapper_params(const SnapOptions& o, std::size_t vertices)
{
    const double margin = 2.0 * o.grid;
    detail::SnapperParams p;
    p.vertex_threshold = o.tolerance + margin;
    p.edge_threshold = o.edge_separation * o.tolerance + margin;
    p.sliver_threshold = o.sliver_factor > 0 ? o.sliver_factor * o.tolerance + margin : 0.0;
    p.max_operations = o.max_operations ? o.max_operations : 20 * vertices + 1000;
    return p;
}

// Polygon features whose own rings cross or overlap, found on the input triangulation:
// a sub-edge the feature owns twice (overlapping edges), or a vertex lying inside two of its
// input edges (two straight edges through one interior point either cross there or overlap).
// A ring vertex touching another edge is not flagged: that is valid for a hole on its shell.
std::vector<bool> self_intersecting(Mesh& mesh, std::size_t features, const Region& region)
{
    std::vector<bool> flag(features, false);
    auto& tri = mesh.tri();
    const std::vector<detail::SubEdgeOwner> owners = mesh.sub_edge_owners();
    std::vector<std::uint32_t> seen;
    for (std::size_t k = 0; k < owners.size();) {
        std::size_t j = k;
        seen.clear();
        for (; j < owners.size() && owners[j].key == owners[k].key; ++j) {
            const detail::Owner& ow = mesh.owner_at(owners[j].owner);
            if (ow.line) continue;
            if (std::find(seen.begin(), seen.end(), ow.feature) != seen.end()) {
                const detail::VertexRecord &a = mesh.vertex(static_cast<std::uint32_t>(owners[k].key >> 32)),
                                           &b = mesh.vertex(static_cast<std::uint32_t>(owners[k].key));
                if (region.contains(0.5 * (a.x + b.x), 0.5 * (a.y + b.y))) flag[ow.feature] = true;
            }
            seen.push_back(ow.feature);
        }
        k = j;
    }
    std::unordered_map<std::uint64_t, int> inside; // (vertex, feature) -> edges passing through
    for (auto cit = tri.constraints_begin(); cit != tri.constraints_end(); ++cit) {
        const detail::Owner& ow = mesh.owner(*cit);
        if (ow.line) continue;
        auto first = tri.vertices_in_constraint_begin(*cit), last = tri.vertices_in_constraint_end(*cit);
        for (auto it = std::next(first); it != last && std::next(it) != last; ++it) {
            const std::uint64_t key = (std::uint64_t{(*it)->info().id} << 32) | ow.feature;
            if (++inside[key] >= 2 && region.contains(mesh.vertex((*it)->info().id).x, mesh.vertex((*it)->info().id).y))
                flag[ow.feature] = true;
        }
    }
    return flag;
}

struct Context {
    const SnapOptions& options;
    std::vector<CleanFeature>& clean;
    Mesh& mesh;
    SnapResult& result;
};

double feature_displacement(Context& c, std::size_t f)
{
    const std::vector<std::uint32_t>& ids = c.mesh.input_vertices(f);
    double worst = 0;
    std::size_t k = 0;
    auto visit = [&](const Coord& p) {
        const detail::VertexRecord& r = c.mesh.vertex(c.mesh.current(ids[k++]));
        if (c.options.report_region.contains(p.x, p.y)) worst = std::max(worst, std::hypot(r.x - p.x, r.y - p.y));
    };
    for (const auto& ring : c.clean[f].rings) std::for_each(ring.points.begin(), ring.points.end(), visit);
    for (const auto& line : c.clean[f].lines) std::for_each(line.begin(), line.end(), visit);
    return worst;
}

void report_outcome(Context& c, std::size_t f, const Geometry& g, double moved)
{
    if (detail::outcome_problems(c.clean[f], g, moved, c.options, c.result.problems)) ++c.result.stats.collapsed_features;
}

// An input edge of a polygon that no longer separates it from the outside (same membership
// on both sides) lies in a part thinner than t that collapsed: a spike, a notch, a corridor
// to a hole. Reported once per feature, at the smallest such place (deterministic).
void report_collapsed_edges(Context& c, const detail::FaceLabels& labels)
{
    std::vector<std::size_t> count(c.clean.size(), 0);
    std::vector<Coord> where(c.clean.size());
    auto& tri = c.mesh.tri();
    auto member = [&](cdt::Face_handle f, std::uint32_t feature) {
        const std::vector<std::uint32_t>& set = labels.sets[f->info().label];
        return std::binary_search(set.begin(), set.end(), feature);
    };
    for (auto cit = tri.constraints_begin(); cit != tri.constraints_end(); ++cit) {
        const detail::Owner& o = c.mesh.owner(*cit);
        if (o.line) continue;
        cdt::Vertex_handle prev;
        for (auto it = tri.vertices_in_constraint_begin(*cit); it != tri.vertices_in_constraint_end(*cit); prev = *it, ++it) {
            cdt::Face_handle fh;
            int i;
            if (prev == cdt::Vertex_handle() || !tri.is_edge(prev, *it, fh, i)) continue;
            if (member(fh, o.feature) != member(fh->neighbor(i), o.feature)) continue;
            const detail::VertexRecord &a = c.mesh.vertex(prev->info().id), &b = c.mesh.vertex((*it)->info().id);
            const Coord mid{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
            if (!c.options.report_region.contains(mid.x, mid.y)) continue;
            if (count[o.feature]++ == 0 || std::tie(mid.x, mid.y) < std::tie(where[o.feature].x, where[o.feature].y))
                where[o.feature] = mid;
        }
    }
    for (std::size_t f = 0; f < c.clean.size(); ++f) {
        if (count[f] == 0 || c.result.features[c.clean[f].index].geometry.empty()) continue;
        c.result.problems.push_back(Problem{c.clean[f].id, ProblemCode::thin_part_collapsed,
            std::to_string(count[f]) + " input edge pieces no longer bound the polygon: a part thinner than the tolerance collapsed",
            where[f].x, where[f].y});
    }
}

// How far each feature's output strays from its input, per input edge: the largest distance
// from a vertex now on that edge's constraint to the original segment. Vertex moves alone miss
// an edge bent by a cascade of splits (each < t, together several t on dense tangles).
std::vector<double> edge_deviation(Context& c)
{
    std::vector<double> worst(c.clean.size(), 0.0);
    auto& tri = c.mesh.tri();
    for (auto cit = tri.constraints_begin(); cit != tri.constraints_end(); ++cit) {
        const detail::Owner& o = c.mesh.owner(*cit);
        const CleanFeature& cf = c.clean[o.feature];
        const std::vector<Coord>& pts = o.line ? cf.lines[o.part] : cf.rings[o.part].points;
        const Coord& a = pts[o.seg];
        const Coord& b = pts[(o.seg + 1) % pts.size()];
        for (auto it = tri.vertices_in_constraint_begin(*cit); it != tri.vertices_in_constraint_end(*cit); ++it) {
            const detail::VertexRecord& r = c.mesh.vertex((*it)->info().id);
            if (!c.options.report_region.contains(r.x, r.y)) continue;
            worst[o.feature] = std::max(worst[o.feature], detail::distance_point_segment(r.x, r.y, a.x, a.y, b.x, b.y));
        }
    }
    return worst;
}

void extract_all(Context& c, const detail::FaceLabels& labels)
{
    const std::vector<double> deviation = edge_deviation(c);
    auto lines = detail::collect_line_edges(c.mesh, c.clean.size());
    for (std::size_t f = 0; f < c.clean.size(); ++f) {
        const CleanFeature& cf = c.clean[f];
        FeatureOutput& out = c.result.features[cf.index];
        out.id = cf.id;
        if (cf.rejected) continue;
        const bool has_z = c.result.features[cf.index].geometry.has_z;
        const detail::ExtractOptions eo{c.options.grid, has_z};
        if (cf.polygonal) {
            out.geometry = detail::extract_polygons(c.mesh, labels.faces_of[f], eo);
        } else {
            std::vector<Coord> starts;
            for (const auto& l : cf.lines) {
                starts.push_back(l.front());
            }
            out.geometry = detail::extract_lines(c.mesh, lines[f], starts, eo);
        }
        out.geometry.has_z = has_z;
        out.max_displacement = std::max(feature_displacement(c, f), deviation[f]);
        c.result.stats.max_displacement = std::max(c.result.stats.max_displacement, out.max_displacement);
        report_outcome(c, f, out.geometry, out.max_displacement);
    }
}

// Vertices the snapper could not settle: every feature with an edge at them is reported.
void report_unresolved(Context& c, const detail::SnapperOutcome& outcome)
{
    const ProblemCode code = outcome.converged ? ProblemCode::separation_not_reached : ProblemCode::not_converged;
    std::vector<std::uint32_t> owners;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> hits; // feature, vertex
    auto& tri = c.mesh.tri();
    for (std::uint32_t v : outcome.unresolved) {
        if (!c.options.report_region.contains(c.mesh.vertex(v).x, c.mesh.vertex(v).y)) continue;
        auto vc = tri.incident_vertices(c.mesh.vertex(v).handle), done = vc;
        do {
            if (tri.is_infinite(vc)) continue;
            c.mesh.owners_of_edge(v, vc->info().id, owners);
            for (std::uint32_t o : owners) hits.emplace_back(c.mesh.owner_at(o).feature, v);
        } while (++vc != done);
    }
    std::sort(hits.begin(), hits.end());
    for (std::size_t k = 0; k < hits.size(); ++k) {
        if (k > 0 && hits[k].first == hits[k - 1].first) continue;
        const detail::VertexRecord& r = c.mesh.vertex(hits[k].second);
        c.result.problems.push_back(Problem{c.clean[hits[k].first].id, code,
            outcome.converged ? "a vertex stays closer than the tolerance allows (split refused: it already snapped into that edge)"
                              : "operation cap reached before the fix-point", r.x, r.y});
    }
}

} // namespace

namespace detail {

bool outcome_problems(const CleanFeature& cf, const Geometry& g, double moved, const SnapOptions& options,
                      std::vector<Problem>& problems)
{
    auto add = [&](ProblemCode code, std::string msg, const Coord& at) {
        problems.push_back(Problem{cf.id, code, std::move(msg), at.x, at.y});
    };
    const Coord at = cf.polygonal ? cf.rings.front().points.front() : cf.lines.front().front();
    if (g.empty()) {
        add(cf.polygonal ? ProblemCode::collapsed_polygon : ProblemCode::collapsed_line,
            cf.polygonal ? "polygon thinner than the tolerance vanished" : "line shorter than the tolerance vanished", at);
        return true;
    }
    std::size_t parts = cf.polygonal ? g.polygons.size() : g.lines.size(), holes = 0;
    for (const Polygon& p : g.polygons) holes += p.rings.size() - 1;
    const std::size_t in_parts = cf.polygonal ? cf.shells : cf.lines.size();
    if (parts < in_parts) add(ProblemCode::part_removed, std::to_string(in_parts - parts) + " of " + std::to_string(in_parts) + " parts vanished", at);
    if (holes < cf.holes) add(ProblemCode::hole_removed, std::to_string(cf.holes - holes) + " of " + std::to_string(cf.holes) + " holes closed", at);
    if (parts > in_parts || holes > cf.holes)
        add(ProblemCode::topology_changed, "a neck thinner than the tolerance collapsed: " + std::to_string(in_parts) + " parts became " + std::to_string(parts) + ", " + std::to_string(cf.holes) + " holes became " + std::to_string(holes), at);
    if (moved > options.max_drift_factor * options.tolerance)
        add(ProblemCode::drift_exceeded, "the boundary moved up to " + std::to_string(moved / options.tolerance) + " x tolerance (cascade of snaps)", at);
    return false;
}

} // namespace detail

SnapResult snap(const std::vector<Feature>& features, const SnapOptions& options)
{
    if (const std::string msg = validate(options); !msg.empty()) throw std::invalid_argument(msg);
    SnapResult result;
    result.stats.input_features = features.size();
    result.features.resize(features.size());
    for (std::size_t i = 0; i < features.size(); ++i) {
        result.features[i].id = features[i].id;
        result.features[i].geometry.has_z = features[i].geometry.has_z;
    }
    Stopwatch clock;
    std::vector<CleanFeature> clean = detail::clean_input(features, options.tolerance, result.problems);
    SnapStats& st = result.stats;
    for (const CleanFeature& cf : clean) {
        for (const auto& ring : cf.rings) st.input_vertices += ring.points.size();
        for (const auto& line : cf.lines) st.input_vertices += line.size();
    }
    const detail::SnapperParams params = snapper_params(options, st.input_vertices);
    Mesh mesh(clean, std::max({params.vertex_threshold, params.edge_threshold, params.sliver_threshold}));
    st.triangulation_vertices = mesh.tri().number_of_vertices() - Mesh::frame_vertices;
    st.intersections = mesh.intersections();
    const std::vector<bool> crossing = self_intersecting(mesh, clean.size(), options.report_region);
    for (std::size_t f = 0; f < clean.size(); ++f)
        if (crossing[f]) result.problems.push_back(Problem{clean[f].id, ProblemCode::self_intersection,
            "rings cross or overlap; repaired with the odd-even rule", clean[f].rings[0].points[0].x, clean[f].rings[0].points[0].y});
    st.seconds_triangulate = clock.lap();
    const detail::SnapperOutcome outcome = detail::run_snapper(mesh, params);
    st.merges = outcome.merges, st.splits = outcome.splits, st.rounds = outcome.rounds;
    st.seconds_snap = clock.lap();
    const detail::FaceLabels labels = detail::label_faces(mesh, clean.size());
    st.seconds_label = clock.lap();
    Context ctx{options, clean, mesh, result};
    extract_all(ctx, labels);
    report_collapsed_edges(ctx, labels);
    report_unresolved(ctx, outcome);
    st.output_vertices = mesh.tri().number_of_vertices() - Mesh::frame_vertices;
    st.seconds_extract = clock.lap();
    std::stable_sort(result.problems.begin(), result.problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
    return result;
}

} // namespace trisnap
