#include "app/collapse_guard.hpp"

#include "config/errors.hpp"
#include "core/snap.hpp"
#include "io/output_driver.hpp"
#include "io/tolerance.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace trisnap {
namespace {

/// More than a tenth of the layer, and more than one feature: the share the guard refuses
/// whatever the tolerance. (In a layer of under ten features one is already over a tenth, and
/// one collapsed sliver is what snapping is for.)
bool most_of(std::size_t dropped, std::size_t features)
{
    return dropped > 1 && dropped * 10 > features;
}

bool from_metres(const Plan& plan)
{
    return plan.config.snap.tolerance_m.has_value();
}

bool failed_tile(const Problem& problem)
{
    return problem.code == ProblemCode::tile_failed;
}

/// "292 of 292 features (collapsed)", "3 of 4 features (1 collapsed, 2 rejected: ...)".
std::string dropped_text(const Drops& drops, std::size_t features)
{
    const std::string rejected = fmt::format("rejected: a coordinate too large for the tolerance at double precision, "
                                             "problem {}", static_cast<int>(ProblemCode::huge_coordinate));
    const std::size_t dropped = drops.collapsed + drops.rejected;
    if (drops.rejected == 0) {
        return fmt::format("{} of {} features (collapsed)", dropped, features);
    }
    if (drops.collapsed == 0) {
        return fmt::format("{} of {} features ({})", dropped, features, rejected);
    }
    return fmt::format("{} of {} features ({} collapsed, {} {})", dropped, features, drops.collapsed, drops.rejected,
                       rejected);
}

/// What to do about rejections: the engine takes coordinates up to 2^44 tolerances (and 2^500).
std::string rejection_advice(const Plan& plan)
{
    const double limit = std::min(std::ldexp(plan.tolerance, 44), k_max_coordinate);
    return fmt::format("coordinates beyond {:g} cannot be snapped at this tolerance (2^44 times it, at most 2^500): "
                       "see the problems in --report; a larger tolerance, or the layer moved nearer the origin, keeps "
                       "them",
                       limit);
}

} // namespace

void check_collapse(const Plan& plan, const Drops& drops, std::size_t features, bool predicted)
{
    if (plan.config.run.allow_collapse || drops.collapsed + drops.rejected == 0) {
        return;
    }
    const bool in_degrees = degrees_above_warning(plan.tolerance, from_metres(plan), plan.layer->GetSpatialRef());
    const bool by_collapses = (in_degrees && drops.collapsed > 0) || most_of(drops.collapsed, features);
    if (!by_collapses && !most_of(drops.collapsed + drops.rejected, features)) {
        return;
    }
    const std::string what =
        predicted ? fmt::format("at least {} of {} features are smaller than the tolerance: snapping would drop them",
                                drops.collapsed, features)
                  : "snapping would drop " + dropped_text(drops, features);
    const std::string advice = by_collapses ? collapse_advice(plan.tolerance, from_metres(plan), *plan.layer)
                                            : rejection_advice(plan);
    const std::string outcome = predicted ? "Stopped; --allow-collapse (or --force) runs it anyway"
                                          : "Nothing was written; --allow-collapse (or --force) writes it anyway";
    throw argument_error(fmt::format("{}: {}; {}. {}", input_label(plan), what, advice, outcome));
}

bool rejected_by_engine(const Problem& problem)
{
    return problem.code == ProblemCode::huge_coordinate;
}

std::set<std::pair<std::uint32_t, std::int64_t>> rejected_features(const ProblemLog& problems)
{
    std::set<std::pair<std::uint32_t, std::int64_t>> out;
    problems.for_each([&](const Problem& p) {
        if (rejected_by_engine(p)) {
            out.emplace(p.layer, p.feature_id);
        }
    });
    return out;
}

Drops count_vanished(stitch::TiledRun& run, const RunResult& result)
{
    const auto rejected = rejected_features(result.problems);
    const std::unique_ptr<stitch::OutputMerger> merger = run.output();
    stitch::OutputItem item;
    Drops drops;
    std::uint32_t layer = 0;
    std::uint64_t layer_end = result.layers.empty() ? 0 : result.layers[0].input; // input positions of `layer`
    while (merger->next(item)) {
        while (item.seq >= layer_end && layer + 1 < result.layers.size()) {
            layer_end += result.layers[++layer].input;
        }
        if (!item.output.geometry.empty() || std::any_of(item.problems.begin(), item.problems.end(), failed_tile)) {
            continue; // written, or reported as 303 (--on-error skip asked for it)
        }
        if (rejected.count({layer, item.output.id})) {
            ++drops.rejected;
        } else {
            ++drops.collapsed;
        }
    }
    return drops;
}

void guard_collapse(const Plan& plan, RunPhases& phases)
{
    if (plan.config.run.allow_collapse || !is_stdout_path(plan.write.path)) {
        return; // a file OUT is checked at the end of the write phase, before its commit
    }
    const Drops drops = count_vanished(phases.tiles(), phases.result());
    spdlog::debug("collapse guard: {} collapsed and {} rejected of {} features would be dropped", drops.collapsed,
                  drops.rejected, phases.result().input);
    check_collapse(plan, drops, phases.result().input);
}

bool smaller_than_tolerance(const Geometry& g, double tolerance)
{
    double xmin = std::numeric_limits<double>::infinity();
    double ymin = xmin;
    double xmax = -xmin;
    double ymax = -xmin;
    auto extend = [&](const Path& path) {
        for (const Coord& c : path) {
            xmin = std::min(xmin, c.x);
            ymin = std::min(ymin, c.y);
            xmax = std::max(xmax, c.x);
            ymax = std::max(ymax, c.y);
        }
    };
    for (const Polygon& p : g.polygons) {
        std::for_each(p.rings.begin(), p.rings.end(), extend);
    }
    std::for_each(g.lines.begin(), g.lines.end(), extend);
    return xmin <= xmax && std::hypot(xmax - xmin, ymax - ymin) < tolerance;
}

} // namespace trisnap
