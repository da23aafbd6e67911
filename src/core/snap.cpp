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

#include "core/evidence.hpp"
#include "core/extraction.hpp"
#include "core/input_cleaning.hpp"
#include "core/labelling.hpp"
#include "core/mesh.hpp"
#include "core/outcome.hpp"
#include "core/shared_boundaries.hpp"
#include "core/snapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace trisnap {
namespace {

using detail::CleanFeature;
using detail::Outline;
using detail::Outlines;
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
    p.verify = o.verify_fixpoint;
    return p;
}

struct Context {
    const SnapOptions& options;
    const Outlines& outlines; ///< the cleaned features' (the mesh's records hold their points)
    Mesh& mesh;
    SnapResult& result;
    detail::WorkMeter& meter;
    double grid; ///< the output grid, 0 when rounding is not safe (see snap())
};

// How far the feature's input points moved: each input point's own record (records never move)
// against the vertex it now is.
double feature_displacement(Context& c, std::size_t f)
{
    double worst = 0;
    for (const std::uint32_t id : c.mesh.input_vertices(f)) {
        const detail::Xy p = c.mesh.xy(id);
        const detail::Xy r = c.mesh.xy(c.mesh.current(id));
        if (c.options.report_region.contains(p.x, p.y)) worst = std::max(worst, std::hypot(r.x - p.x, r.y - p.y));
    }
    return worst;
}

void report_outcome(Context& c, std::size_t f, const Geometry& g, double moved)
{
    if (detail::outcome_problems(c.outlines[f], g, moved, c.options, c.result.problems)) ++c.result.stats.collapsed_features;
}

/// By feature id, then code (the order snap() promises).
void sort_problems(std::vector<Problem>& problems)
{
    std::stable_sort(problems.begin(), problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
}

// True when every input point lies within t of every other (the diagonal of their bounding box
// is shorter than t, with a margin for its rounding). Merges and splits only ever put vertices
// inside the convex hull of the input, so no two output vertices could be t apart: the only
// answer the contract allows is that every feature collapses. It is given without building the
// triangulation, whose queue would hold an event for every pair of vertices (about 10^9 for
// Andorra at t = 1 degree: it ran out of memory at 12.7 GB).
bool all_within_tolerance(const std::vector<CleanFeature>& clean, double t)
{
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    bool any = false;
    auto add = [&](const Coord& c) {
        x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), x1 = std::max(x1, c.x), y1 = std::max(y1, c.y);
        any = true;
    };
    for (const CleanFeature& cf : clean) {
        if (cf.rejected) continue;
        for (const auto& ring : cf.rings) std::for_each(ring.points.begin(), ring.points.end(), add);
        for (const auto& line : cf.lines) std::for_each(line.begin(), line.end(), add);
    }
    const double dx = x1 - x0, dy = y1 - y0;
    return any && dx * dx + dy * dy < t * t * (1.0 - 1e-9);
}

// Problem 210 (core/shared_boundaries.hpp): decided here when this run sees everything; a tile
// (a bounded report region) gives its evidence to the stitch instead, which merges its tiles'.
void give_shared(const Outlines& clean, const detail::SharedBoundaryEvidence& shared,
                 const std::vector<bool>& written, const SnapOptions& options, SnapResult& result)
{
    std::vector<std::vector<SharedBoundary>> seen = shared.by_feature(clean.features);
    const bool everything = options.report_region.unbounded() && options.data_extent.unbounded() && options.report_cores.empty();
    std::vector<bool> written_at(result.features.size(), false); // by input position
    for (std::size_t f = 0; f < clean.size(); ++f) {
        written_at[clean[f].index] = written[f];
    }
    const auto other_written = [&](const SharedBoundary& s) { return written_at[s.other_position]; };
    const auto name = [](std::int64_t other) { return "FID " + std::to_string(other); }; // as the stitch names it
    for (std::size_t f = 0; f < clean.size(); ++f) {
        if (everything) {
            detail::report_lost_boundaries(clean[f].id, clean[f].index, written[f], options.tolerance, seen[f],
                                           other_written, name, result.problems);
        } else {
            result.features[clean[f].index].shared = std::move(seen[f]);
        }
    }
}

/// The output table (104 bytes a feature: 26 MB of Andorra x43, beside the snapper when it was
/// made first), made once the triangulation is freed: each feature's id and whether it has z.
void make_outputs(SnapResult& result, const Outlines& clean, const std::vector<bool>& has_z)
{
    result.features.resize(clean.size());
    for (const Outline& cf : clean.features) {
        result.features[cf.index].id = cf.id;
        result.features[cf.index].geometry.has_z = has_z[cf.index];
    }
}

/// Each polygon feature's boundary edges by vertex id, taken out of the triangulation so it can
/// be freed before the outputs are made: features in blocks of FaceLabels::k_block, one exact
/// allocation per block, each made as the labels' block of the same features is freed.
struct Boundaries {
    std::vector<std::vector<detail::IdEdge>> blocks;
    std::vector<std::size_t> first{0}; ///< prefix sums of the edges per feature, over all features
    std::span<const detail::IdEdge> of(std::size_t feature) const
    {
        const std::size_t k = detail::FaceLabels::k_block;
        const std::size_t base = first[feature / k * k];
        return {blocks[feature / k].data() + (first[feature] - base), first[feature + 1] - first[feature]};
    }
};

Boundaries take_boundaries(Context& c, detail::FaceLabels& labels)
{
    const std::size_t k = detail::FaceLabels::k_block;
    Boundaries b;
    b.first.reserve(c.outlines.size() + 1);
    std::vector<detail::IdEdge> scratch;
    for (std::size_t lo = 0; lo < c.outlines.size(); lo += k) {
        scratch.clear();
        const std::size_t hi = std::min(c.outlines.size(), lo + k);
        for (std::size_t f = lo; f < hi; ++f) {
            if (c.outlines[f].polygonal && !c.outlines[f].rejected) {
                detail::append_boundary_edges(c.mesh, labels.faces_of(f), scratch);
            }
            b.first.push_back(b.first[lo] + scratch.size());
        }
        labels.release_block(lo);
        b.blocks.emplace_back(scratch.begin(), scratch.end());
    }
    return b;
}

void extract_block(Context& c, const Boundaries& boundaries, const std::vector<double>& deviation,
                   const detail::LineEdges& lines, std::size_t lo, std::size_t hi)
{
    for (std::size_t f = lo; f < hi; ++f) {
        const Outline& cf = c.outlines[f];
        FeatureOutput& out = c.result.features[cf.index];
        out.id = cf.id;
        if (cf.rejected) continue;
        const bool has_z = c.result.features[cf.index].geometry.has_z;
        const detail::ExtractOptions eo{c.grid, has_z};
        if (cf.polygonal) {
            out.geometry = detail::assemble_boundary(c.mesh, boundaries.of(f), eo);
        } else {
            out.geometry = detail::extract_lines(c.mesh, lines.of(f), c.outlines.starts(f), eo);
        }
        out.geometry.has_z = has_z;
        out.max_displacement = std::max(feature_displacement(c, f), deviation[f]);
        c.result.stats.max_displacement = std::max(c.result.stats.max_displacement, out.max_displacement);
        report_outcome(c, f, out.geometry, out.max_displacement);
        if ((f & 255) == 255) c.meter.advance(f, c.outlines.size());
    }
}

} // namespace

namespace detail {

bool outcome_problems(const Outline& cf, const Geometry& g, double moved, const SnapOptions& options,
                      std::vector<Problem>& problems)
{
    auto add = [&](ProblemCode code, std::string msg, const Coord& at) {
        problems.push_back(Problem{cf.id, code, std::move(msg), at.x, at.y});
    };
    const Coord at{cf.x, cf.y};
    if (g.empty()) {
        add(cf.polygonal ? ProblemCode::collapsed_polygon : ProblemCode::collapsed_line,
            cf.polygonal ? "polygon thinner than the tolerance vanished" : "line shorter than the tolerance vanished", at);
        return true;
    }
    std::size_t parts = cf.polygonal ? g.polygons.size() : g.lines.size(), holes = 0;
    for (const Polygon& p : g.polygons) holes += p.rings.size() - 1;
    const std::size_t in_parts = cf.parts;
    if (parts < in_parts) add(ProblemCode::part_removed, std::to_string(in_parts - parts) + " of " + std::to_string(in_parts) + " parts vanished", at);
    if (holes < cf.holes) add(ProblemCode::hole_removed, std::to_string(cf.holes - holes) + " of " + std::to_string(cf.holes) + " holes closed", at);
    if (parts > in_parts || holes > cf.holes)
        add(ProblemCode::topology_changed, "a neck thinner than the tolerance collapsed: " + std::to_string(in_parts) + " parts became " + std::to_string(parts) + ", " + std::to_string(cf.holes) + " holes became " + std::to_string(holes), at);
    if (moved > options.max_drift_factor * options.tolerance)
        add(ProblemCode::drift_exceeded, "the boundary moved up to " + std::to_string(moved / options.tolerance) + " x tolerance (cascade of snaps)", at);
    return false;
}

} // namespace detail

namespace {

// `release`, when given, is `features` itself: emptied once the cleaned copy exists.
SnapResult snap_features(const std::vector<Feature>& features, const SnapOptions& options, std::vector<Feature>* release)
{
    if (const std::string msg = validate(options); !msg.empty()) throw std::invalid_argument(msg);
    SnapResult result;
    result.stats.input_features = features.size();
    std::vector<bool> has_z(features.size());
    for (std::size_t i = 0; i < features.size(); ++i) {
        has_z[i] = features[i].geometry.has_z;
    }
    Stopwatch clock;
    std::vector<CleanFeature> clean = detail::clean_input(features, options.tolerance, result.problems);
    if (release != nullptr) {
        std::vector<Feature>().swap(*release); // `features` is empty from here on
    }
    SnapStats& st = result.stats;
    for (const CleanFeature& cf : clean) {
        for (const auto& ring : cf.rings) st.input_vertices += ring.points.size();
        for (const auto& line : cf.lines) st.input_vertices += line.size();
    }
    const detail::SnapperParams params = snapper_params(options, st.input_vertices);
    detail::WorkMeter meter(options.progress, st.input_vertices);
    if (all_within_tolerance(clean, options.tolerance)) {
        const Outlines outlines = detail::make_outlines(clean);
        make_outputs(result, outlines, has_z);
        for (const Outline& cf : outlines.features) {
            if (!cf.rejected && detail::outcome_problems(cf, Geometry{}, 0.0, options, result.problems)) ++st.collapsed_features;
        }
        sort_problems(result.problems);
        st.seconds_triangulate = clock.lap();
        meter.finish();
        return result;
    }
    // From here on only the features' outlines are kept: the mesh's records hold their points.
    Outlines outlines;
    Mesh mesh(std::move(clean), std::max({params.vertex_threshold, params.edge_threshold, params.sliver_threshold}),
              &meter, outlines);
    st.triangulation_vertices = mesh.tri().number_of_vertices() - Mesh::frame_vertices;
    st.intersections = mesh.intersections();
    const std::vector<bool> crossing = detail::self_intersecting(mesh, outlines.size(), options.report_region);
    for (std::size_t f = 0; f < outlines.size(); ++f)
        if (crossing[f]) result.problems.push_back(Problem{outlines[f].id, ProblemCode::self_intersection,
            "rings cross or overlap; repaired with the odd-even rule", outlines[f].x, outlines[f].y});
    detail::SharedBoundaryEvidence shared(options.report_region, options.report_cores, options.data_extent);
    shared.before(mesh);
    st.seconds_triangulate = clock.lap();
    const detail::SnapperOutcome outcome = detail::run_snapper(mesh, params, &meter);
    mesh.release_search_scratch();
    st.merges = outcome.merges;
    st.splits = outcome.splits;
    st.rounds = outcome.rounds;
    st.faces_visited = outcome.faces_visited;
    st.fixpoint_misses = outcome.fixpoint_misses;
    st.seconds_snap = clock.lap();
    meter.begin(detail::WorkMeter::Step::labelling);
    detail::FaceLabels labels = detail::label_faces(mesh, outlines.size());
    st.seconds_label = clock.lap();
    meter.begin(detail::WorkMeter::Step::extraction);
    // Rounding to the grid keeps the output valid only at the fix-point, where every vertex is
    // at least the thresholds (with their 2g margins) from every edge. A run stopped short of it
    // (operation cap, refused split: 205/207) can hold a vertex next to an edge, and rounding
    // then crossed it: an invalid ring, found by fuzz_snap (t = 1.5e65, grid t/4, a cap of 18
    // operations). Such a run is written unrounded, and 205/207 say so.
    const bool round = outcome.converged && outcome.unresolved.empty();
    Context ctx{options, outlines, mesh, result, meter, round ? options.grid : 0.0};
    // The outputs are made after the triangulation is freed, in the memory it held: first what
    // reads the owner table, then the polygons' boundaries out of the faces (the labels' face
    // lists freed as they go), then the triangulation itself. Andorra x43 untiled: the heap in
    // use peaked at the end of the extraction, CGAL's 230 MB beside the outputs' 58 MB.
    const std::vector<double> deviation = detail::edge_deviation(mesh, outlines.size(), options.report_region);
    const detail::LineEdges lines = detail::collect_line_edges(mesh, outlines.size());
    const detail::CollapsedEdges collapsed = detail::collapsed_edges(mesh, options.report_region);
    std::vector<Problem> unresolved;
    detail::report_unresolved(mesh, outcome, outlines.features, options.report_region, options.grid, unresolved);
    shared.after(mesh);
    st.output_vertices = mesh.tri().number_of_vertices() - Mesh::frame_vertices;
    mesh.release_owners();
    Boundaries boundaries = take_boundaries(ctx, labels);
    mesh.release_triangulation();
    make_outputs(result, outlines, has_z);
    for (std::size_t lo = 0; lo < outlines.size(); lo += detail::FaceLabels::k_block) {
        extract_block(ctx, boundaries, deviation, lines, lo, std::min(outlines.size(), lo + detail::FaceLabels::k_block));
        std::vector<detail::IdEdge>().swap(boundaries.blocks[lo / detail::FaceLabels::k_block]);
    }
    std::vector<bool> written(outlines.size());
    for (std::size_t f = 0; f < outlines.size(); ++f) {
        written[f] = !result.features[outlines[f].index].geometry.empty();
    }
    detail::report_collapsed_edges(collapsed, outlines.features, written, result.problems);
    result.problems.insert(result.problems.end(), std::make_move_iterator(unresolved.begin()),
                           std::make_move_iterator(unresolved.end()));
    give_shared(outlines, shared, written, options, result);
    st.seconds_extract = clock.lap();
    sort_problems(result.problems);
    meter.finish();
    return result;
}

} // namespace

SnapResult snap(const std::vector<Feature>& features, const SnapOptions& options)
{
    return snap_features(features, options, nullptr);
}

SnapResult snap(std::vector<Feature>&& features, const SnapOptions& options)
{
    return snap_features(features, options, &features);
}

} // namespace trisnap
