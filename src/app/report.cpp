#include "app/report.hpp"

#include "app/memory.hpp"
#include "app/text.hpp"
#include "app/version.hpp"
#include "io/io_error.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <ostream>
#include <stdexcept>
#include <sys/resource.h>

namespace trisnap {
namespace {

using nlohmann::ordered_json;

ordered_json config_json(const Plan& plan)
{
    const SnapConfig& s = plan.config.snap;
    ordered_json snap;
    if (s.tolerance) snap["tolerance"] = *s.tolerance;
    if (s.tolerance_m) snap["tolerance_m"] = *s.tolerance_m;
    snap["edge_separation"] = s.edge_separation;
    snap["sliver_factor"] = s.sliver_factor;
    snap["grid"] = s.grid;
    snap["max_drift_factor"] = s.max_drift_factor;
    snap["max_operations"] = s.max_operations;
    const TilingConfig& t = plan.config.tiling;
    ordered_json tiling = {{"size", t.size}, {"vertex_budget", t.vertex_budget}, {"halo", t.halo},
                           {"max_growth", t.max_growth}, {"no_tiles", t.no_tiles}};
    return {{"snap", snap}, {"tiling", tiling}, {"run", {{"threads", plan.config.run.threads}, {"memory_limit", plan.config.run.memory_limit},
                                                     {"allow_collapse", plan.config.run.allow_collapse},
                                                     {"on_error", plan.config.run.on_error}}},
            {"tolerance_layer_units", plan.tolerance}, {"tolerance_note", plan.tolerance_note}};
}

ordered_json counts_json(const RunResult& r)
{
    return {{"input", r.input}, {"written", r.written}, {"snapped", r.snapped},
            {"rejected", r.rejected}, {"dropped", r.dropped}, {"unwritable", r.unwritable},
            {"problems", r.problems.size()}, {"input_vertices", r.input_vertices},
            {"fids_renumbered", r.fids_renumbered}};
}

ordered_json stats_json(const SnapStats& s)
{
    return {{"input_features", s.input_features}, {"input_vertices", s.input_vertices},
            {"triangulation_vertices", s.triangulation_vertices}, {"output_vertices", s.output_vertices},
            {"intersections", s.intersections}, {"merges", s.merges}, {"splits", s.splits},
            {"rounds", s.rounds}, {"collapsed_features", s.collapsed_features},
            {"max_displacement", s.max_displacement}};
}

ordered_json timings_json(const RunResult& r, double total)
{
    const SnapStats& s = r.stats;
    ordered_json phases = ordered_json::object();
    ordered_json cpu = ordered_json::object();
    for (const PhaseRecord& p : r.phases) {
        phases[p.name] = p.seconds;
        cpu[p.name] = p.cpu_seconds;
    }
    // CPU: every thread's user + system time, per phase and for the process so far (its start,
    // GDAL's drivers loaded, is in no phase). A phase's CPU over its seconds is how many cores
    // it kept busy.
    return {{"read", r.seconds_read}, {"snap", r.seconds_snap}, {"write", r.seconds_write}, {"total", total},
            {"phases", phases}, {"cpu_phases", cpu}, {"cpu_process", process_cpu_seconds()},
            {"engine", {{"triangulate", s.seconds_triangulate}, {"snap", s.seconds_snap},
                        {"label", s.seconds_label}, {"extract", s.seconds_extract}}}};
}

ordered_json memory_json(const RunResult& r)
{
    ordered_json peaks = ordered_json::object();
    for (const PhaseRecord& p : r.phases) {
        peaks[p.name] = static_cast<double>(p.peak_rss) / 1048576.0;
    }
    const RunBudget& b = r.budget;
    return {{"mode", b.on_disk ? "out_of_core" : "in_memory"}, {"reason", b.reason},
            {"limit_bytes", b.memory_limit}, {"estimate_bytes", b.estimate}, {"tile_pool_bytes", r.memory_pool},
            {"work_dir", b.on_disk ? ordered_json(b.work_dir) : ordered_json(nullptr)}, {"resumed", r.resumed},
            {"spool_bytes", r.spool_bytes}, {"peak_mb_after_phase", peaks}};
}

ordered_json tiling_json(const RunResult& r)
{
    if (!r.tiled) return {{"tiled", false}};
    const stitch::StitchStats& s = r.stitch;
    ordered_json out = {{"tiled", true}, // the options are in config.tiling
        {"leaves", s.leaves}, {"tiles", s.tiles}, {"tile_runs", s.tile_runs}, {"seam_merges", s.seam_merges},
        {"halo_growths", s.halo_growths}, {"unbounded_cascades", s.unbounded_cascades},
        {"copied_features", s.copied_features}, {"assembled_features", s.assembled_features},
        {"tiles_failed", s.tiles_dropped}, {"failed_features", s.failed_features},
        {"seconds_tiles", s.seconds_tiles}, {"seconds_stitch", s.seconds_stitch}};
    ordered_json list = ordered_json::array();
    for (const stitch::TileReport& t : r.tiles)
        list.push_back({{"id", t.id}, {"leaves", t.leaves}, {"core", {t.core.xmin, t.core.ymin, t.core.xmax, t.core.ymax}},
                        {"halo", t.halo}, {"halo_growths", t.growths}, {"runs", t.runs}, {"features", t.features},
                        {"input_vertices", t.input_vertices}, {"owned_edges", t.output_edges_owned},
                        {"problems", t.problems}, {"seconds", t.seconds},
                        {"failed", t.failed ? ordered_json(t.failure) : ordered_json(nullptr)}});
    out["list"] = list;
    return out;
}

ordered_json coordinate(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }

// With several layers each problem says whose FID it carries ("layer" after "fid").
ordered_json problem_json(const Plan& plan, const Problem& p)
{
    ordered_json item = {{"fid", p.feature_id}};
    if (plan.layers.size() > 1) {
        item["layer"] = plan.layers.at(p.layer)->GetName();
    }
    item.update(ordered_json{{"code", static_cast<int>(p.code)}, {"name", problem_name(p.code)},
                             {"message", p.message}, {"x", coordinate(p.x)}, {"y", coordinate(p.y)}});
    return item;
}

const char* fids_kept(const Plan& plan, bool renumbered)
{
    return plan.keeps_fids && !renumbered ? "kept" : "orig_fid";
}

// Several layers: each one's name, output layer, FIDs and accounting.
ordered_json layers_json(const Plan& plan, const RunResult& r)
{
    ordered_json list = ordered_json::array();
    for (std::size_t k = 0; k < r.layers.size(); ++k) {
        const LayerCounts& c = r.layers[k];
        const std::uint64_t problems = r.problems.in_layer(static_cast<std::uint32_t>(k));
        list.push_back({{"name", plan.layers[k]->GetName()}, {"output_layer", output_layer_name(plan, k)},
                        {"fids", fids_kept(plan, c.fids_renumbered)},
                        {"counts", {{"input", c.input}, {"written", c.written}, {"snapped", c.snapped},
                                    {"rejected", c.rejected}, {"dropped", c.dropped}, {"unwritable", c.unwritable},
                                    {"problems", problems}, {"input_vertices", c.input_vertices},
                                    {"fids_renumbered", c.fids_renumbered}}}});
    }
    return list;
}

ordered_json by_code_json(const ProblemLog& problems)
{
    ordered_json out = ordered_json::object();
    for (const auto& [code, n] : problems.by_code())
        out[std::to_string(code)] = {{"name", problem_name(static_cast<ProblemCode>(code))}, {"count", n}};
    return out;
}

// One layer: its name; several: their names in order (the output layers have the same).
ordered_json names_json(const Plan& plan, bool output)
{
    if (plan.layers.size() == 1) {
        return output ? output_layer_name(plan, 0) : std::string(plan.layer->GetName());
    }
    ordered_json names = ordered_json::array();
    for (std::size_t k = 0; k < plan.layers.size(); ++k) {
        names.push_back(output ? output_layer_name(plan, k) : std::string(plan.layers[k]->GetName()));
    }
    return names;
}

ordered_json io_json(const Plan& plan, const RunResult& r)
{
    return {{"input", {{"path", plan.input_path}, {"driver", plan.input_driver}, {"layer", names_json(plan, false)},
                       {"crs", plan.crs}, {"features", r.input}}},
            {"output", {{"path", plan.write.path}, {"driver", plan.output_driver}, {"layer", names_json(plan, true)},
                        {"fids", fids_kept(plan, r.fids_renumbered)},
                        {"features", r.written}}}};
}

} // namespace

double peak_memory_mb()
{
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0; // Linux reports KiB
}

void write_json_streaming_last_array(const ordered_json& document, const std::string& key,
                                     const std::function<void(const std::function<void(const ordered_json&)>&)>& items,
                                     const std::function<void(std::string_view)>& put)
{
    const std::string text = document.dump(2, ' ', false, ordered_json::error_handler_t::replace);
    const std::string tail = "\"" + key + "\": []\n}";
    if (text.size() < tail.size() || text.compare(text.size() - tail.size(), tail.size(), tail) != 0) {
        throw std::logic_error("write_json_streaming_last_array: \"" + key + "\" is not the last member, or not empty");
    }
    put(std::string_view(text).substr(0, text.size() - 4)); // all but the empty array and the brace
    bool first = true;
    items([&](const ordered_json& item) {
        // dump(2) of the whole indents an array element of a top-level member by 4 spaces, and
        // every line of it by 4 more than dumping it alone.
        std::string lines = item.dump(2, ' ', false, ordered_json::error_handler_t::replace);
        std::string out = first ? "[\n    " : ",\n    ";
        out.reserve(out.size() + lines.size() + 64);
        for (char c : lines) {
            out += c;
            if (c == '\n') {
                out += "    ";
            }
        }
        put(out);
        first = false;
    });
    put(first ? "[]\n}" : "\n  ]\n}");
}

void write_report(const Plan& plan, const RunResult& result, double total_seconds,
                  const std::function<void(std::string_view)>& put)
{
    ordered_json report = {{"tool", "trisnap"}, {"version", k_version}, {"command", "snap"}};
    report.update(io_json(plan, result));
    report["config"] = config_json(plan);
    report["counts"] = counts_json(result);
    if (plan.layers.size() > 1) {
        report["layers"] = layers_json(plan, result);
    }
    report["engine"] = stats_json(result.stats);
    report["timings_s"] = timings_json(result, total_seconds);
    report["peak_memory_mb"] = peak_memory_mb();
    report["memory"] = memory_json(result);
    report["tiling"] = tiling_json(result);
    report["problems_by_code"] = by_code_json(result.problems);
    report["problems"] = ordered_json::array();
    write_json_streaming_last_array(report, "problems", [&](const auto& item) {
        result.problems.for_each([&](const Problem& p) { item(problem_json(plan, p)); });
    }, put);
    put("\n");
}

std::string report_text(const Plan& plan, const RunResult& result, double total_seconds)
{
    std::string text;
    write_report(plan, result, total_seconds, [&](std::string_view chunk) { text.append(chunk); });
    return text;
}

void stage_report(CommitGroup& group, const std::string& path, const Plan& plan, const RunResult& result,
                  double total_seconds)
{
    stage_text_stream(group, path, [&](const std::function<void(std::string_view)>& put) {
        write_report(plan, result, total_seconds, put);
    }, plan.write.protected_files, "--report");
}

void print_summary(std::ostream& out, const Plan& plan, const RunResult& r, double total_seconds)
{
    const std::size_t not_written = r.input - r.written;
    std::string causes = r.stitch.failed_features == 0
                             ? ""
                             : fmt::format(", {} of them in failed tiles", r.stitch.failed_features);
    if (r.dropped_rejected > 0) {
        causes += fmt::format(", {} of them rejected (109 huge coordinate)", r.dropped_rejected);
    }
    out << fmt::format("{} in, {} written, {} not written ({} rejected on input, {} dropped by the engine{}, {} refused by the driver)\n",
                       count_of(r.input, "feature"), r.written, not_written, r.rejected, r.dropped, causes, r.unwritable);
    for (std::size_t k = 0; plan.layers.size() > 1 && k < r.layers.size(); ++k) {
        const LayerCounts& c = r.layers[k];
        out << fmt::format("  layer '{}': {} in, {} written, {} not written ({} rejected, {} dropped, {} refused)\n",
                           plan.layers[k]->GetName(), c.input, c.written, c.input - c.written, c.rejected, c.dropped,
                           c.unwritable);
    }
    std::string codes;
    for (const auto& [code, n] : r.problems.by_code())
        codes += fmt::format("{}{} {} x{}", codes.empty() ? "" : ", ", code,
                             problem_name(static_cast<ProblemCode>(code)), n);
    out << fmt::format("{}{}{}\n", count_of(r.problems.size(), "problem"), codes.empty() ? "" : ": ", codes);
    std::string phases;
    for (const PhaseRecord& p : r.phases) {
        phases += fmt::format("{}{} {:.2f}", phases.empty() ? "" : ", ", p.name, p.seconds);
    }
    out << fmt::format("tolerance {} ({}); time {:.2f} s ({}); peak memory {:.0f} MB\n", plan.tolerance,
                       plan.tolerance_note, total_seconds, phases, peak_memory_mb());
    if (r.budget.on_disk) {
        out << fmt::format("out of core ({}): work files up to {} in {}{}\n", r.budget.reason, format_size(r.spool_bytes),
                           r.budget.work_dir, r.resumed ? " (resumed)" : "");
    }
    out << fmt::format("output: {} ({})\n", plan.write.path, plan.output_driver);
}

} // namespace trisnap
