// Fuzz target: the engine (trisnap::snap) on small coordinate sets decoded from the bytes
// (fuzz_snap_decode.hpp) at arbitrary tolerances. Options the engine refuses (validate()) end
// the input. Every accepted input is checked with the independent contract checker
// (tests/support): valid output, vertex-vertex >= t, vertex-edge >= edge_separation*t, every
// feature in the output or excused by a "not written" problem, no new overlaps (a fold between two
// features that both carry 205 counts apart: the checker's unfinished_codes); any breach
// prints the input and aborts, so libFuzzer keeps it as a crash.
// TRISNAP_FUZZ_PRINT=1 prints each decoded input and its problems (to read a corpus entry).
// Drift (Hausdorff) is not judged here: on arbitrary tangles the engine reports its own drift
// (206). A feature is flagged (exempt from the shared-boundary check) only when the engine
// reported a drift code for that very feature (the checker's rule), and every feature of an
// input may legitimately be flagged (all collapse at a tolerance larger than the layer, all
// cross themselves), so the bound is the number of features, not less: a smaller one would call
// such inputs breaches. (Checking each flag against independent evidence works only for 201/202,
// an empty output, which the shared-boundary check leaves out anyway.)
#include "fuzz_snap_decode.hpp"
#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

using namespace trisnap;

/// The engine admits (205/207) where its separation does not hold; such a run is judged on
/// everything else.
bool separation_waived(const SnapResult& result)
{
    return count_code(result, ProblemCode::not_converged) > 0 ||
           count_code(result, ProblemCode::separation_not_reached) > 0;
}

bool breached(const ContractReport& r, const SnapOptions& o, bool waive_separation)
{
    const double slack = 1.0 - 1e-9;
    const bool spacing = r.min_vertex_vertex >= o.tolerance * slack &&
                         r.min_vertex_edge >= o.edge_separation * o.tolerance * slack;
    return r.n_missing > 0 || r.n_invalid > 0 || r.n_overlaps_new > 0 || r.n_shared_lost > 0 ||
           (!spacing && !waive_separation);
}

// The checker's geometry library (GEOS) is not scale-invariant at huge magnitudes: at coordinates
// near 1e111 its MakeValid dropped a triangle of an invalid input that it kept at 2^-40 times the
// size, so an overlap the input had looked new in the output (found by fuzz_snap; the engine's
// output was the exact 2^-40 scale of its output at 1e111). Scaling by a power of two is exact in
// binary floating point and the contract is stated in units of t, so the checker judges input
// and output scaled by 2^k with t in [1, 2): every coordinate the engine accepts (|c| <= 2^44 t,
// else problem 109) lands within 2^45, where GEOS is exact enough.
int checker_exponent(double tolerance)
{
    return -std::ilogb(tolerance);
}

void scale_path(Path& path, int k)
{
    for (Coord& c : path) {
        c.x = std::ldexp(c.x, k);
        c.y = std::ldexp(c.y, k);
    }
}

Geometry scaled(Geometry g, int k)
{
    for (Polygon& polygon : g.polygons) {
        for (Path& ring : polygon.rings) {
            scale_path(ring, k);
        }
    }
    for (Path& line : g.lines) {
        scale_path(line, k);
    }
    return g;
}

std::vector<Feature> scaled(std::vector<Feature> features, int k)
{
    for (Feature& f : features) {
        f.geometry = scaled(std::move(f.geometry), k);
    }
    return features;
}

SnapResult scaled(SnapResult result, int k)
{
    for (FeatureOutput& f : result.features) {
        f.geometry = scaled(std::move(f.geometry), k);
    }
    return result;
}

SnapOptions scaled(SnapOptions options, int k)
{
    options.tolerance = std::ldexp(options.tolerance, k);
    options.grid = std::ldexp(options.grid, k);
    return options;
}

ContractReport check_scaled(const fuzz::SnapProblem& problem, const SnapResult& result)
{
    const int k = checker_exponent(problem.options.tolerance);
    const SnapOptions options = scaled(problem.options, k);
    return check_contract(checked_features(scaled(problem.features, k)), checked_features(scaled(result, k)),
                          reported_problems(result), options.tolerance,
                          engine_rules(options, problem.features.size()));
}

/// `id;WKT` lines, as fuzz::describe() writes the input.
template <class F>
std::string wkt_lines(const std::vector<F>& features)
{
    std::string out;
    for (const F& f : features) {
        out += std::to_string(f.id) + ";" + to_wkt(f.geometry) + "\n";
    }
    return out;
}

[[noreturn]] void report_breach(const fuzz::SnapProblem& problem, const SnapResult& result,
                                const ContractReport& report)
{
    const int k = checker_exponent(problem.options.tolerance);
    const std::string scaled_input = wkt_lines(scaled(problem.features, k));
    const std::string scaled_output = wkt_lines(scaled(result, k).features);
    std::fprintf(stderr, "fuzz_snap: contract breached (checked with coordinates and t scaled by 2^%d)\n%s\nproblems:\n%s\ninput:\n%s"
                 "input scaled by 2^%d:\n%soutput scaled by 2^%d:\n%s",
                 k, report.summary().c_str(), problem_lines(result.problems).c_str(), fuzz::describe(problem).c_str(), k,
                 scaled_input.c_str(), k, scaled_output.c_str());
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const fuzz::SnapProblem problem = fuzz::decode_snap_problem(data, size);
    if (const std::string refused = validate(problem.options); !refused.empty()) {
        if (std::getenv("TRISNAP_FUZZ_PRINT")) {
            std::fprintf(stderr, "refused: %s\n", refused.c_str());
        }
        return 0;
    }
    const SnapResult result = snap(problem.features, problem.options);
    if (std::getenv("TRISNAP_FUZZ_PRINT")) {
        std::fprintf(stderr, "%sproblems:\n%s", fuzz::describe(problem).c_str(), problem_lines(result.problems).c_str());
    }
    if (result.features.size() != problem.features.size()) {
        std::fprintf(stderr, "fuzz_snap: %zu outputs for %zu inputs\n", result.features.size(),
                     problem.features.size());
        std::abort();
    }
    const ContractReport report = check_scaled(problem, result);
    const SnapOptions checked = scaled(problem.options, checker_exponent(problem.options.tolerance));
    if (breached(report, checked, separation_waived(result))) {
        report_breach(problem, result, report);
    }
    return 0;
}
