#include "app/pipeline.hpp"

#include "config/errors.hpp"

#include "app/interrupt.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"
#include "io/reader.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <unordered_set>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Everything read from the layer, in input order.
struct Loaded {
    std::vector<InputFeature> records;
    std::vector<Feature> features;          ///< what the engine gets
    std::vector<std::ptrdiff_t> engine_of;  ///< record -> index in features, or -1
    bool renumber = false;                  ///< engine ids are record indices, not FIDs
};

std::size_t vertices_of(const Geometry& g)
{
    std::size_t n = 0;
    for (const Polygon& p : g.polygons)
        for (const Path& r : p.rings) n += r.size();
    for (const Path& l : g.lines) n += l.size();
    return n;
}

/// FIDs are used as engine ids unless some are missing or repeated.
bool fids_usable(const std::vector<InputFeature>& records)
{
    std::unordered_set<std::int64_t> seen;
    for (const InputFeature& r : records)
        if (r.fid == OGRNullFID || !seen.insert(r.fid).second) return false;
    return true;
}

void build_engine_input(Loaded& loaded, RunResult& result)
{
    loaded.renumber = !fids_usable(loaded.records);
    loaded.engine_of.assign(loaded.records.size(), -1);
    for (std::size_t i = 0; i < loaded.records.size(); ++i) {
        InputFeature& r = loaded.records[i];
        if (!r.geometry) continue;
        loaded.engine_of[i] = static_cast<std::ptrdiff_t>(loaded.features.size());
        result.input_vertices += vertices_of(*r.geometry);
        const std::int64_t id = loaded.renumber ? static_cast<std::int64_t>(i) : r.fid;
        loaded.features.push_back(Feature{id, std::move(*r.geometry)});
        r.geometry.reset();
    }
    result.snapped = loaded.features.size();
    result.fids_renumbered = loaded.renumber;
}

Loaded read_all(Plan& plan, Progress& progress, RunResult& result)
{
    const auto start = Clock::now();
    Loaded loaded;
    LayerReader reader(*plan.dataset, *plan.layer);
    progress.start("read", plan.feature_count >= 0 ? plan.feature_count : reader.count_hint());
    while (auto feature = reader.next()) {
        if (feature->problem) result.problems.push_back(*feature->problem);
        if (feature->rejected) ++result.rejected;
        loaded.records.push_back(std::move(*feature));
        progress.update(static_cast<std::int64_t>(loaded.records.size()));
    }
    progress.finish();
    result.input = loaded.records.size();
    if (loaded.records.empty())
        throw io_error(plan.input_path, plan.layer->GetName(),
                       plan.layer->GetAttrQueryString() || plan.layer->GetSpatialFilter()
                           ? "no feature matches --where/--bbox: nothing to snap"
                           : "the layer is empty: nothing to snap");
    build_engine_input(loaded, result);
    result.seconds_read = since(start);
    return loaded;
}

SnapResult run_engine(const Loaded& loaded, const Plan& plan, Progress& progress, RunResult& result)
{
    const auto start = Clock::now();
    SnapResult snapped;
    try {
        if (plan.tiled) {
            progress.start("snap", -1); // the phase names are an interface (--json-progress); tiles done are the units
            stitch::TiledResult tiled = stitch::snap_tiled(loaded.features, plan.options, plan.tiling,
                                                           [&](std::size_t done, std::size_t) { progress.update(static_cast<std::int64_t>(done)); });
            snapped = std::move(tiled.result);
            result.tiled = true;
            result.tiles = std::move(tiled.tiles);
            result.stitch = tiled.stitch;
        } else {
            progress.start("snap", static_cast<std::int64_t>(loaded.features.size()));
            snapped = snap(loaded.features, plan.options);
            progress.update(static_cast<std::int64_t>(loaded.features.size()));
        }
    } catch (const std::invalid_argument& e) { // options the data made unusable (a tile size too small for the extent)
        throw argument_error(e.what());
    } catch (const std::exception& e) {
        throw std::runtime_error(std::string("snapping failed: ") + e.what());
    }
    if (snapped.features.size() != loaded.features.size())
        throw std::runtime_error("snapping failed: the engine returned a different number of features");
    progress.finish();
    result.stats = snapped.stats;
    result.seconds_snap = since(start);
    return snapped;
}

/// Engine problems carry engine ids; reports carry input FIDs.
void collect_engine_problems(const Loaded& loaded, const SnapResult& snapped, RunResult& result)
{
    for (Problem p : snapped.problems) {
        if (loaded.renumber && p.feature_id >= 0 && static_cast<std::size_t>(p.feature_id) < loaded.records.size())
            p.feature_id = loaded.records[static_cast<std::size_t>(p.feature_id)].fid;
        result.problems.push_back(std::move(p));
    }
}

Problem feature_problem(std::int64_t fid, ProblemCode code, std::string message)
{
    Problem p;
    p.feature_id = fid;
    p.code = code;
    p.message = std::move(message);
    p.x = p.y = std::numeric_limits<double>::quiet_NaN();
    return p;
}

/// The geometry to write for record i, or nullptr with `dropped` set when the engine returned nothing.
OGRGeometry* output_geometry(Loaded& loaded, const SnapResult& snapped, std::size_t i, bool& dropped)
{
    InputFeature& r = loaded.records[i];
    dropped = false;
    if (loaded.engine_of[i] < 0) return r.feature->StealGeometry(); // passed through unchanged
    const FeatureOutput& out = snapped.features[static_cast<std::size_t>(loaded.engine_of[i])];
    dropped = out.geometry.empty();
    return dropped ? nullptr : to_ogr(out.geometry, r.input_type);
}

void write_all(Plan& plan, Loaded& loaded, const SnapResult& snapped, RunResult& result, Progress& progress)
{
    const auto start = Clock::now();
    plan.write.renumber = loaded.renumber;
    LayerWriter writer(plan.write, *plan.layer);
    const InterruptGuard interrupt;
    std::set<std::int64_t> with_problem;
    for (const Problem& p : result.problems) with_problem.insert(p.feature_id);
    progress.start("write", static_cast<std::int64_t>(loaded.records.size()));
    for (std::size_t i = 0; i < loaded.records.size(); ++i) {
        InputFeature& r = loaded.records[i];
        progress.update(static_cast<std::int64_t>(i));
        interrupt.check();
        if (r.rejected) continue;
        bool dropped = false;
        OGRGeometry* geometry = output_geometry(loaded, snapped, i, dropped);
        if (dropped) {
            ++result.dropped;
            if (!with_problem.count(r.fid))
                result.problems.push_back(feature_problem(r.fid, r.input_type == wkbPolygon || r.input_type == wkbMultiPolygon
                    ? ProblemCode::collapsed_polygon : ProblemCode::collapsed_line, "the feature vanished when snapped; not written"));
            continue;
        }
        if (std::string error = writer.write(*r.feature, r.fid, geometry); !error.empty()) {
            ++result.unwritable;
            result.problems.push_back(feature_problem(r.fid, ProblemCode::unwritable_feature, error));
        }
        r.feature.reset();
    }
    progress.update(static_cast<std::int64_t>(loaded.records.size()));
    progress.finish();
    interrupt.check();
    writer.commit();
    for (Problem& p : writer.take_problems()) {
        result.problems.push_back(std::move(p)); // values and field names the format changed
    }
    for (const std::string& line : writer.warnings()) {
        spdlog::warn("{}: {}", plan.write.path, line); // one line per field and kind, not per feature
    }
    result.written = writer.written();
    result.seconds_write = since(start);
}

} // namespace

RunResult run_pipeline(Plan& plan, Progress& progress)
{
    RunResult result;
    Loaded loaded = read_all(plan, progress, result);
    const SnapResult snapped = run_engine(loaded, plan, progress, result);
    collect_engine_problems(loaded, snapped, result);
    write_all(plan, loaded, snapped, result, progress);
    std::stable_sort(result.problems.begin(), result.problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
    return result;
}

} // namespace trisnap
