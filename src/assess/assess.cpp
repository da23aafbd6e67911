// assess_layers: read both layers, match, then run each family of measures.
#include "assess/assess.hpp"
#include "assess/layer_pair.hpp"
#include "assess/measures.hpp"
#include "assess/snap_report.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;

/// Records the seconds since the last lap under a phase name.
class PhaseClock {
public:
    explicit PhaseClock(AssessReport& report) : m_report(report) {}
    void lap(const char* name)
    {
        const auto now = Clock::now();
        m_report.timings.emplace_back(name, std::chrono::duration<double>(now - m_last).count());
        m_last = now;
    }
    void finish() { m_report.seconds = std::chrono::duration<double>(Clock::now() - m_start).count(); }

private:
    AssessReport& m_report;
    Clock::time_point m_start = Clock::now();
    Clock::time_point m_last = m_start;
};

void check_tolerance(double t)
{
    if (!(t > 0) || !std::isfinite(t)) {
        throw std::invalid_argument(fmt::format("--tolerance must be finite and > 0, got {}", t));
    }
}

assess::Excuses excuses_of(const AssessOptions& options)
{
    return options.report ? assess::Excuses(*options.report) : assess::Excuses();
}

/// The located problems of the snap report, for sites and pictures.
std::vector<AssessExample> located_problems(const AssessOptions& options)
{
    std::vector<AssessExample> out;
    if (!options.report) {
        return out;
    }
    for (const assess::ReportedProblem& p : options.report->problems) {
        if (p.at) {
            AssessExample e;
            e.fid_a = p.fid;
            e.x = p.at->x;
            e.y = p.at->y;
            e.value = p.code;
            e.text = p.name;
            out.push_back(e);
        }
    }
    return out;
}

void run_measures(assess::Context& c, const AssessOptions& options, AssessReport& r, PhaseClock& clock)
{
    c.match = assess::measure_matching(c.a, c.b, c.excuses, r, c.k);
    c.input_of.assign(c.b.features.size(), -1);
    for (std::size_t i = 0; i < c.match.size(); ++i) {
        if (c.match[i] >= 0) {
            c.input_of[static_cast<std::size_t>(c.match[i])] = static_cast<std::int64_t>(i);
        }
    }
    clock.lap("matching");
    const std::vector<std::uint8_t> invalid = assess::measure_validity(c, r);
    clock.lap("validity");
    assess::measure_separations(c, r);
    clock.lap("separations");
    assess::measure_overlaps(c, invalid, r);
    clock.lap("overlaps");
    assess::measure_gaps(c, r);
    clock.lap("gaps");
    assess::measure_hausdorff(c, r);
    clock.lap("hausdorff");
    assess::measure_worst(c, options.worst, r);
    clock.lap("worst");
}

void measure(const assess::LayerData& a, const assess::LayerData& b, const std::string& matched_by,
             const AssessOptions& options, AssessReport& r, PhaseClock& clock)
{
    r.matched_by = matched_by;
    r.layer_a = a.name;
    r.layer_b = b.name;
    r.tolerance = options.tolerance;
    r.snap_report = options.report ? options.report->path : "";
    r.n_in = static_cast<std::int64_t>(a.features.size());
    r.n_out = static_cast<std::int64_t>(b.features.size());
    r.problems = located_problems(options);
    assess::Context c{a, b, {}, {}, options.tolerance, options.max_examples, excuses_of(options)};
    run_measures(c, options, r, clock);
}

} // namespace

AssessReport assess_layers(LayerSource original, LayerSource snapped, const AssessOptions& options)
{
    check_tolerance(options.tolerance);
    AssessReport r;
    PhaseClock clock(r);
    const assess::LayerPair pair = assess::read_pair(original, snapped, options.key_field);
    clock.lap("read");
    measure(pair.a, pair.b, pair.matched_by, options, r, clock);
    clock.finish();
    return r;
}

AssessReport assess_data(const assess::LayerData& a, const assess::LayerData& b, const std::string& matched_by,
                         const AssessOptions& options)
{
    check_tolerance(options.tolerance);
    AssessReport r;
    PhaseClock clock(r);
    measure(a, b, matched_by, options, r, clock);
    clock.finish();
    return r;
}

bool AssessReport::contract_holds() const { return contract_failures().empty(); }

std::vector<std::string> AssessReport::contract_failures() const
{
    std::vector<std::string> failures;
    const auto count = [&](std::int64_t n, const std::string& what) {
        if (n > 0) {
            failures.push_back(fmt::format("{} {}", n, what));
        }
    };
    const double t = tolerance;
    count(n_invalid, "invalid");
    count(n_crossings_new, "new crossings");
    count(n_overlaps_new, "new overlaps");
    count(gaps_new - excused_counts.gaps, "new gaps");
    count(n_missing - excused_counts.missing, "missing");
    const std::int64_t separations = n_vv_breaches + n_ve_breaches - excused_counts.separations;
    if (separations > 0) {
        failures.push_back(fmt::format("{} separation breaches (min vertex-vertex {:.3g} T, min vertex-edge {:.3g} T)",
                                       separations, min_vertex_vertex.value_or(t) / t, min_vertex_edge.value_or(t) / t));
    }
    if (n_drift - excused_counts.drift > 0) {
        failures.push_back(fmt::format("{} features drift > 2T (max {:.3g} T)", n_drift - excused_counts.drift, max_hausdorff / t));
    }
    return failures;
}

} // namespace trisnap
