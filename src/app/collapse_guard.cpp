#include "app/collapse_guard.hpp"

#include "config/errors.hpp"
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

} // namespace

void check_collapse(const Plan& plan, std::size_t dropped, std::size_t features, bool predicted)
{
    if (plan.config.run.allow_collapse || dropped == 0) {
        return;
    }
    const bool in_degrees = degrees_above_warning(plan.tolerance, from_metres(plan), plan.layer->GetSpatialRef());
    if (!in_degrees && !most_of(dropped, features)) {
        return;
    }
    const std::string what =
        predicted ? fmt::format("at least {} of {} features are smaller than the tolerance: snapping would drop them",
                                dropped, features)
                  : fmt::format("snapping would drop {} of {} features (collapsed)", dropped, features);
    const std::string outcome = predicted ? "Stopped; --allow-collapse (or --force) runs it anyway"
                                          : "Nothing was written; --allow-collapse (or --force) writes it anyway";
    throw argument_error(fmt::format("{}: {}; {}. {}", input_label(plan), what,
                                     collapse_advice(plan.tolerance, from_metres(plan), *plan.layer), outcome));
}

std::size_t count_vanished(stitch::TiledRun& run)
{
    const std::unique_ptr<stitch::OutputMerger> merger = run.output();
    stitch::OutputItem item;
    std::size_t vanished = 0;
    while (merger->next(item)) {
        const bool failed_tile = std::any_of(item.problems.begin(), item.problems.end(),
                                             [](const Problem& p) { return p.code == ProblemCode::tile_failed; });
        if (item.output.geometry.empty() && !failed_tile) {
            ++vanished;
        }
    }
    return vanished;
}

void guard_collapse(const Plan& plan, RunPhases& phases)
{
    if (plan.config.run.allow_collapse || !is_stdout_path(plan.write.path)) {
        return; // a file OUT is checked at the end of the write phase, before its commit
    }
    const std::size_t vanished = count_vanished(phases.tiles());
    spdlog::debug("collapse guard: {} of {} features would be dropped", vanished, phases.result().input);
    check_collapse(plan, vanished, phases.result().input);
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
