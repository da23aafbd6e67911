// The report as a table for people: one row per measure, what the snap report explains, the
// verdict and the worst sites.
#include "assess/assess.hpp"

#include <fmt/format.h>

namespace trisnap {
namespace {

constexpr std::size_t k_excused_listed = 5;

class Table {
public:
    void row(const char* name, const std::string& value) { m_out += fmt::format("  {:<22}{}\n", name, value); }
    void more(const std::string& value) { m_out += fmt::format("  {:<22}{}\n", "", value); }
    std::string& text() { return m_out; }

private:
    std::string m_out;
};

std::string separation(const std::optional<double>& v, double t, std::int64_t breaches, const char* limit)
{
    if (!v) {
        return "none";
    }
    std::string text = fmt::format("{:.6g} ({:.3g} T)  (contract >= {})", *v, *v / t, limit);
    return breaches > 0 ? text + fmt::format(", {} vertices closer", breaches) : text;
}

void measures(const AssessReport& r, Table& table)
{
    const double t = r.tolerance;
    table.row("features", fmt::format("{} in, {} out, {} matched by {}", r.n_in, r.n_out, r.n_matched, r.matched_by));
    table.row("missing / extra", fmt::format("{} / {}", r.n_missing, r.n_extra));
    table.row("attribute mismatches", std::to_string(r.n_attr_mismatch));
    table.row("empty outputs", std::to_string(r.n_empty));
    if (r.n_unmeasurable > 0) {
        table.row("unmeasurable", fmt::format("{} (a coordinate not finite or beyond 1e150)", r.n_unmeasurable));
    }
    table.row("invalid polygons", std::to_string(r.n_invalid));
    table.row("overlapping pairs", fmt::format("{} (area {:.6g}), {} new", r.n_overlaps, r.overlap_area, r.n_overlaps_new));
    table.row("new gaps", fmt::format("{} of {} shared boundaries", r.gaps_new, r.n_shared_in));
    table.row("crossings", fmt::format("{}, {} new", r.n_crossings, r.n_crossings_new));
    table.row("min vertex-vertex", separation(r.min_vertex_vertex, t, r.n_vv_breaches, "T"));
    table.row("min vertex-edge", separation(r.min_vertex_edge, t, r.n_ve_breaches, "T/2"));
    table.row("max Hausdorff", fmt::format("{:.6g} ({:.3g} T)  (contract <= 2T), {} features > 2T", r.max_hausdorff,
                                           r.max_hausdorff / t, r.n_drift));
    table.row("p99 Hausdorff", fmt::format("{:.6g} ({:.3g} T)", r.p99_hausdorff, r.p99_hausdorff / t));
    table.row("area change", fmt::format("{:+.3g} %", 100 * r.area_change));
}

std::string excused_item(const AssessExample& e, double t)
{
    std::string fids = fmt::format("fid {}", e.fid_a);
    if (e.fid_b >= 0 && e.fid_b != e.fid_a) {
        fids += fmt::format(" / {}", e.fid_b);
    }
    const bool distance = e.text == "drift" || e.text == "vertex-edge" || e.text == "vertex-vertex";
    const std::string value = distance ? fmt::format(" {:.3g} T", e.value / t) : "";
    return fmt::format("{} {}{} ({})", fids, e.text, value, e.excused_by);
}

void excuses(const AssessReport& r, Table& table)
{
    if (r.snap_report.empty()) {
        return;
    }
    const ExcusedCounts& c = r.excused_counts;
    if (c.total() == 0) {
        table.row("excused", "none needed (" + r.snap_report + ")");
        return;
    }
    table.row("excused", fmt::format("{} by {}: {} missing, {} drift, {} gaps, {} separations", c.total(), r.snap_report,
                                     c.missing, c.drift, c.gaps, c.separations));
    for (std::size_t i = 0; i < std::min(r.excused.size(), k_excused_listed); ++i) {
        table.more(excused_item(r.excused[i], r.tolerance));
    }
    if (c.total() > static_cast<std::int64_t>(k_excused_listed)) {
        table.more(fmt::format("... ({} in all; --json lists {})", c.total(), r.excused.size()));
    }
}

void verdict(const AssessReport& r, Table& table)
{
    std::string text = contract_verdict(r);
    const std::int64_t excused = r.excused_counts.total();
    text += excused > 0 ? fmt::format(" (new defects only; {} explained by the snap report)", excused) : " (new defects only)";
    table.row("contract", text);
}

} // namespace

std::vector<std::string> worst_site_lines(const std::vector<assess::Site>& sites, double tolerance)
{
    std::vector<std::string> lines;
    for (std::size_t i = 0; i < sites.size(); ++i) {
        const assess::Site& s = sites[i];
        std::string line = fmt::format("#{} {}, {}", i + 1, assess::describe_site(s, tolerance), assess::site_place(s));
        lines.push_back(s.excused_by.empty() ? line : line + "; excused by " + s.excused_by);
    }
    return lines;
}

std::string contract_verdict(const AssessReport& r)
{
    const std::vector<std::string> failures = r.contract_failures();
    std::string text = failures.empty() ? "holds" : "does NOT hold:";
    for (const std::string& f : failures) {
        text += " " + f + ";";
    }
    return text;
}

std::string assess_report_table(const AssessReport& r)
{
    Table table;
    table.text() = fmt::format("assess '{}' -> '{}', tolerance T = {:g}\n", r.layer_a, r.layer_b, r.tolerance);
    measures(r, table);
    excuses(r, table);
    verdict(r, table);
    const std::vector<std::string> worst = worst_site_lines(r.worst, r.tolerance);
    for (std::size_t i = 0; i < worst.size(); ++i) {
        if (i == 0) {
            table.row("worst sites", worst[i]);
        } else {
            table.more(worst[i]);
        }
    }
    std::string phases;
    for (const auto& [name, seconds] : r.timings) {
        phases += fmt::format("{}{} {:.2f}", phases.empty() ? "" : ", ", name, seconds);
    }
    table.row("time", fmt::format("{:.2f} s ({})", r.seconds, phases));
    return table.text();
}

} // namespace trisnap
