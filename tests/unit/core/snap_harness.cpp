#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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

bool is_drift_code(ProblemCode code) {
    switch (code) {
    case ProblemCode::self_intersection:
    case ProblemCode::collapsed_polygon:
    case ProblemCode::collapsed_line:
    case ProblemCode::part_removed:
    case ProblemCode::hole_removed:
    case ProblemCode::drift_exceeded:
    case ProblemCode::thin_part_collapsed:
        return true;
    default:
        return false;
    }
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

std::vector<std::int64_t> problem_ids(const SnapResult& result) {
    std::vector<std::int64_t> ids;
    for (const Problem& p : result.problems)
        ids.push_back(p.feature_id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
}

std::vector<std::int64_t> drift_reported_ids(const SnapResult& result) {
    std::vector<std::int64_t> ids;
    for (const Problem& p : result.problems)
        if (is_drift_code(p.code))
            ids.push_back(p.feature_id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
}

CheckedRun snap_and_check(const std::vector<Feature>& input, const SnapOptions& options) {
    CheckedRun run;
    auto start = std::chrono::steady_clock::now();
    run.result = snap(input, options);
    run.seconds_snap = seconds_since(start);
    start = std::chrono::steady_clock::now();
    run.report = check_contract(checked_features(input), checked_features(run.result),
                                problem_ids(run.result), options.tolerance,
                                options.edge_separation, drift_reported_ids(run.result));
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
        << " invalid=" << r.n_invalid << " missing=" << r.n_missing << " problems={";
    for (const auto& [code, n] : codes)
        out << code << ":" << n << " ";
    out << "} snap=" << run.seconds_snap << "s check=" << run.seconds_check << "s";
    return out.str();
}

} // namespace trisnap
