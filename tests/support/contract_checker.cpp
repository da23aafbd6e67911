#include "contract_checker.hpp"

#include "checker_detail.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace trisnap {
namespace checker_detail {

void Examples::add(const std::string& kind, const std::string& line) {
    if (m_counts[kind]++ < per_kind)
        m_lines.push_back(line);
}

std::string point_text(double x, double y) {
    char buf[64];
    std::string out = "(";
    out.append(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
    out += ' ';
    out.append(buf, std::to_chars(buf, buf + sizeof buf, y).ptr);
    return out + ")";
}

std::string distance_text(double d, double t) {
    char buf[64];
    std::string out;
    out.append(buf, std::to_chars(buf, buf + sizeof buf, d / t, std::chars_format::general, 4).ptr);
    out += "t (";
    out.append(buf, std::to_chars(buf, buf + sizeof buf, d, std::chars_format::general, 6).ptr);
    return out + ")";
}

namespace {

bool has_code(const std::vector<int>& codes, int code) {
    return std::find(codes.begin(), codes.end(), code) != codes.end();
}

/// Ids with a problem whose code is in `codes`, sorted and unique.
std::vector<std::int64_t> ids_with(const std::vector<ReportedProblem>& problems,
                                   const std::vector<int>& codes) {
    std::vector<std::int64_t> ids;
    for (const ReportedProblem& p : problems) {
        if (has_code(codes, p.code)) {
            ids.push_back(p.id);
        }
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
}

bool contains(const std::vector<std::int64_t>& sorted, std::int64_t id) {
    return std::binary_search(sorted.begin(), sorted.end(), id);
}

bool is_output(const Side& out, std::int64_t id) {
    auto it = out.by_id.find(id);
    return it != out.by_id.end() && out.features[it->second].present();
}

void count_presence(const Side& in, const Side& out, const std::vector<std::int64_t>& not_written,
                    ContractReport& report, Examples& examples) {
    report.n_in = in.features.size();
    for (const SideFeature& f : out.features) {
        report.n_out += f.present() ? 1 : 0;
    }
    for (const SideFeature& f : in.features) {
        if (is_output(out, f.id) || contains(not_written, f.id)) {
            continue;
        }
        ++report.n_missing;
        examples.add("missing", "missing: id " + std::to_string(f.id) +
                                    " has no output and no problem saying it is not written");
    }
}

void count_flagged(const Side& out, const std::vector<std::int64_t>& flagged, ContractReport& report,
                   Examples& examples) {
    for (std::int64_t id : flagged) {
        if (!is_output(out, id)) {
            continue;
        }
        ++report.n_flagged;
        if (report.n_flagged > report.max_flagged) {
            examples.add("flagged", "flagged beyond the case's allowance of " +
                                        std::to_string(report.max_flagged) + ": id " + std::to_string(id));
        }
    }
}

/// Why an output feature is not an acceptable output of its input, or "" when it is.
std::string output_defect(const GeosContext& ctx, const Side& in, const SideFeature& f) {
    if (!f.parse_error.empty())
        return "unreadable WKT: " + f.parse_error;
    if (!f.present())
        return {};
    auto it = in.by_id.find(f.id);
    if (it == in.by_id.end())
        return "id is not in the input";
    const SideFeature& source = in.features[it->second];
    if (source.present() && (source.polygonal != f.polygonal || source.lineal != f.lineal))
        return "geometry dimension differs from the input's";
    if (!f.polygonal && !f.lineal)
        return "neither polygonal nor lineal";
    return invalid_reason(ctx, f);
}

void check_validity(const GeosContext& ctx, const Side& in, const Side& out,
                    ContractReport& report, Examples& examples) {
    for (const SideFeature& f : out.features) {
        const std::string defect = output_defect(ctx, in, f);
        if (defect.empty())
            continue;
        ++report.n_invalid;
        examples.add("invalid", "invalid: id " + std::to_string(f.id) + ": " + defect);
    }
}

std::string min_text(double d, double t) {
    return std::isinf(d) ? std::string("none within 2t") : distance_text(d, t);
}

} // namespace
} // namespace checker_detail

ContractReport check_contract(const std::vector<CheckedFeature>& input,
                              const std::vector<CheckedFeature>& output,
                              const std::vector<ReportedProblem>& problems, double tolerance,
                              const ContractRules& rules) {
    using namespace checker_detail;
    if (!(tolerance > 0.0) || !std::isfinite(tolerance))
        throw std::invalid_argument("check_contract: tolerance must be finite and > 0");
    GeosContext ctx;
    // The engine refuses coordinates beyond 2^44 t (problem 109); the input is measured up to
    // twice that, beyond it only accounted for (checker_geos.cpp, read_feature).
    const Side in = load_side(ctx, input, true, std::ldexp(tolerance, 45));
    const Side out = load_side(ctx, output, false);
    const std::vector<std::int64_t> exempt = ids_with(problems, rules.drift_codes);
    ContractReport report;
    report.tolerance = tolerance;
    report.max_flagged = rules.max_flagged;
    Examples examples(report.examples);
    count_presence(in, out, ids_with(problems, rules.not_written_codes), report, examples);
    count_flagged(out, exempt, report, examples);
    check_validity(ctx, in, out, report, examples);
    measure_spacing(out, tolerance, rules.edge_factor, report, examples);
    measure_hausdorff(in, out, tolerance, exempt, report, examples);
    check_pairs(ctx, in, out, tolerance, exempt, ids_with(problems, rules.lost_boundary_codes),
                ids_with(problems, rules.unfinished_codes), report, examples);
    return report;
}

ContractReport check_contract(const std::vector<CheckedFeature>& input,
                              const std::vector<CheckedFeature>& output, double tolerance) {
    return check_contract(input, output, {}, tolerance, ContractRules{});
}

bool ContractReport::ok(double t, double edge_factor, double max_drift) const {
    const double slack = 1.0 - 1e-9; // distances computed in floating point
    return n_missing == 0 && n_invalid == 0 && min_vertex_vertex >= t * slack &&
           min_vertex_edge >= edge_factor * t * slack && max_hausdorff <= max_drift &&
           n_overlaps_new == 0 && n_shared_lost == 0 && n_flagged <= max_flagged;
}

std::string ContractReport::summary() const {
    using checker_detail::distance_text;
    using checker_detail::min_text;
    const double t = tolerance > 0.0 ? tolerance : 1.0;
    std::ostringstream s;
    s << "contract at t=" << tolerance << ": " << n_in << " in, " << n_out << " out, "
      << n_missing << " missing, " << n_invalid << " invalid, " << n_overlaps_new
      << " new overlaps (" << n_overlaps_new_reported << " more where the run stopped short), " << n_shared_lost << " shared boundaries lost (" << n_shared_lost_reported
      << " more reported), " << n_flagged
      << " flagged (at most " << max_flagged << " allowed)\n"
      << "  min vertex-vertex " << min_text(min_vertex_vertex, t) << " (" << n_close_vertex_pairs
      << " pairs < t), min vertex-edge " << min_text(min_vertex_edge, t) << " ("
      << n_close_vertex_edge << " pairs < edge factor), max Hausdorff "
      << distance_text(max_hausdorff, t) << " (id " << max_hausdorff_id << ")\n";
    for (const std::string& line : examples)
        s << "  " << line << '\n';
    return s.str();
}

::testing::AssertionResult contract_holds(const ContractReport& report, double t,
                                          double edge_factor, double max_drift_factor) {
    if (report.ok(t, edge_factor, max_drift_factor * t))
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "contract broken (edge factor " << edge_factor << ", max drift "
           << max_drift_factor << "t)\n"
           << report.summary();
}

} // namespace trisnap
