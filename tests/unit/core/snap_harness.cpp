#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <sstream>

namespace trisnap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool finite(const Path& path) {
    return std::all_of(path.begin(), path.end(),
                       [](const Coord& c) { return std::isfinite(c.x) && std::isfinite(c.y); });
}

/// GEOS rejects what the engine repairs (unclosed rings, rings under 4 points, NaN), so the
/// checker gets a stand-in: rings closed, too-short rings and lines dropped (a polygon whose
/// shell goes, goes entirely), non-finite features emptied. The engine's repairs of those are
/// tested through its problem codes instead.
Geometry checkable(const Geometry& g) {
    Geometry out;
    out.type = g.type;
    out.has_z = g.has_z;
    for (const Polygon& p : g.polygons) {
        Polygon q;
        for (Path ring : p.rings) {
            if (!finite(ring))
                return Geometry{};
            if (!ring.empty() && !(ring.front() == ring.back()))
                ring.push_back(ring.front());
            if (ring.size() >= 4)
                q.rings.push_back(std::move(ring));
            else if (q.rings.empty())
                break; // no shell, no polygon
        }
        if (!q.rings.empty())
            out.polygons.push_back(std::move(q));
    }
    for (const Path& line : g.lines) {
        if (!finite(line))
            return Geometry{};
        if (line.size() >= 2)
            out.lines.push_back(line);
    }
    return out;
}

} // namespace

std::vector<int> code_numbers(std::initializer_list<ProblemCode> codes) {
    std::vector<int> out;
    for (ProblemCode c : codes) {
        out.push_back(static_cast<int>(c));
    }
    return out;
}

const std::vector<int>& drift_codes() {
    static const std::vector<int> codes = code_numbers(
        {ProblemCode::self_intersection, ProblemCode::collapsed_polygon, ProblemCode::collapsed_line,
         ProblemCode::part_removed, ProblemCode::hole_removed, ProblemCode::drift_exceeded,
         ProblemCode::thin_part_collapsed});
    return codes;
}

ContractRules engine_rules(const SnapOptions& options, std::size_t max_flagged) {
    ContractRules rules;
    rules.edge_factor = options.edge_separation;
    rules.not_written_codes = not_written_codes();
    rules.drift_codes = drift_codes();
    rules.lost_boundary_codes = lost_boundary_codes();
    // A run the operation cap stopped is written as it stood (205 on the features near what was
    // still too close); a fold between two such features is the one case an unfinished run may hold.
    rules.unfinished_codes = code_numbers({ProblemCode::not_converged});
    rules.max_flagged = max_flagged;
    return rules;
}

std::vector<ReportedProblem> reported_problems(const SnapResult& result) {
    std::vector<ReportedProblem> out;
    out.reserve(result.problems.size());
    for (const Problem& p : result.problems) {
        out.push_back({p.feature_id, static_cast<int>(p.code)});
    }
    return out;
}

std::vector<CheckedFeature> checked_features(const std::vector<Feature>& features) {
    std::vector<CheckedFeature> out;
    out.reserve(features.size());
    for (const Feature& f : features) {
        const Geometry g = checkable(f.geometry);
        out.push_back({f.id, g.empty() ? std::string() : to_wkt(g)});
    }
    return out;
}

std::vector<CheckedFeature> checked_features(const SnapResult& result) {
    std::vector<CheckedFeature> out;
    out.reserve(result.features.size());
    for (const FeatureOutput& f : result.features)
        out.push_back({f.id, f.geometry.empty() ? std::string() : to_wkt(f.geometry)});
    return out;
}

CheckedRun snap_and_check(const std::vector<Feature>& input, const SnapOptions& options,
                          std::size_t max_flagged) {
    CheckedRun run;
    // Every checked run also verifies the snapper's fix-point: a full scan at the end must find
    // no event the local re-discovery after each edit missed.
    SnapOptions verified = options;
    verified.verify_fixpoint = true;
    auto start = std::chrono::steady_clock::now();
    run.result = snap(input, verified);
    run.seconds_snap = seconds_since(start);
    EXPECT_EQ(run.result.stats.fixpoint_misses, 0u) << "snapping events the engine's re-discovery missed";
    start = std::chrono::steady_clock::now();
    run.report = check_contract(checked_features(input), checked_features(run.result),
                                reported_problems(run.result), options.tolerance,
                                engine_rules(options, max_flagged));
    run.seconds_check = seconds_since(start);
    return run;
}

SnapOptions options_at(double tolerance, double grid) {
    SnapOptions o;
    o.tolerance = tolerance;
    o.grid = grid;
    return o;
}

std::string problem_lines(const std::vector<Problem>& problems) {
    std::vector<std::pair<std::int64_t, int>> rows;
    for (const Problem& p : problems)
        rows.emplace_back(p.feature_id, static_cast<int>(p.code));
    std::sort(rows.begin(), rows.end());
    std::ostringstream out;
    for (const auto& [id, code] : rows)
        out << id << ' ' << code << '\n';
    return out.str();
}

std::map<std::int64_t, std::string> output_by_id(const SnapResult& result) {
    std::map<std::int64_t, std::string> out;
    for (const FeatureOutput& f : result.features)
        out[f.id] = to_wkt(f.geometry);
    return out;
}

std::size_t count_code(const SnapResult& result, ProblemCode code) {
    return static_cast<std::size_t>(std::count_if(result.problems.begin(), result.problems.end(),
                                                  [&](const Problem& p) { return p.code == code; }));
}

bool has_problem(const SnapResult& result, std::int64_t id, ProblemCode code) {
    return std::any_of(result.problems.begin(), result.problems.end(),
                       [&](const Problem& p) { return p.feature_id == id && p.code == code; });
}

std::vector<Feature> output_as_input(const SnapResult& result) {
    std::vector<Feature> out;
    for (const FeatureOutput& f : result.features)
        if (!f.geometry.empty())
            out.push_back({f.id, f.geometry});
    return out;
}

std::string figures_line(const std::string& name, const CheckedRun& run, double t) {
    const ContractReport& r = run.report;
    std::map<int, std::size_t> codes;
    for (const Problem& p : run.result.problems)
        ++codes[static_cast<int>(p.code)];
    std::ostringstream out;
    out << "[figures] " << name << " t=" << t << " in=" << r.n_in << " out=" << r.n_out
        << " vertices=" << run.result.stats.input_vertices << "->" << run.result.stats.output_vertices
        << " min_vv=" << r.min_vertex_vertex / t << "t min_ve=" << r.min_vertex_edge / t
        << "t max_hausdorff=" << r.max_hausdorff / t << "t (id " << r.max_hausdorff_id << ")"
        << " overlaps_new=" << r.n_overlaps_new << " shared_lost=" << r.n_shared_lost
        << " invalid=" << r.n_invalid << " missing=" << r.n_missing << " flagged=" << r.n_flagged
        << " problems={";
    for (const auto& [code, n] : codes)
        out << code << ":" << n << " ";
    out << "} snap=" << run.seconds_snap << "s check=" << run.seconds_check << "s";
    return out.str();
}

} // namespace trisnap
