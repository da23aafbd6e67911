#include "app/pipeline.hpp"

#include "app/collapse_guard.hpp"
#include "app/run_phases.hpp"
#include "app/version.hpp"
#include "config/errors.hpp"
#include "io/writer.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

nlohmann::json input_files(const Plan& plan)
{
    nlohmann::json files = nlohmann::json::array();
    char** list = plan.dataset->GetFileList();
    for (char** f = list; f && *f; ++f) {
        std::error_code ec;
        const std::filesystem::path p = std::filesystem::weakly_canonical(*f, ec);
        const auto size = std::filesystem::file_size(p, ec);
        const auto time = std::filesystem::last_write_time(p, ec).time_since_epoch().count();
        files.push_back({{"path", p.string()}, {"size", ec ? 0 : size}, {"mtime", static_cast<std::int64_t>(time)}});
    }
    CSLDestroy(list);
    return files;
}

// The layer's name, or (several layers) their names in order: a resume with other layers, or
// the same in another order, is another run.
nlohmann::ordered_json layer_list(const Plan& plan)
{
    if (plan.layers.size() == 1) {
        return plan.layer->GetName();
    }
    nlohmann::ordered_json names = nlohmann::ordered_json::array();
    for (OGRLayer* layer : plan.layers) {
        names.push_back(layer->GetName());
    }
    return names;
}

} // namespace

void commit_outputs(CommitGroup& outputs, InterruptGuard& interrupt)
{
    interrupt.check_at("report-staged");
    outputs.set_before_rename([&] { interrupt.check_at("before-rename"); });
    outputs.commit();
    interrupt.outputs_in_place();
    signal_point("after-rename");
}

std::vector<bool> renumbered_layers(const RunResult& result)
{
    std::vector<bool> renumber;
    for (const LayerCounts& c : result.layers) {
        renumber.push_back(c.fids_renumbered);
    }
    return renumber;
}

RunResult run_pipeline(Plan& plan, WorkDir& work, const RunBudget& budget, Progress& progress, InterruptGuard& interrupt)
{
    RunPhases phases(work, budget, progress, interrupt, plan.options, plan.tiling);
    phases.read(plan);
    // The output is created now, before any snapping: a layer or field the driver refuses stops
    // the run before the long part.
    plan.write.renumber = renumbered_layers(phases.result());
    LayerWriter writer(plan.write, plan.layers);
    phases.open_tiles();
    const auto snap_start = Clock::now();
    phases.spool();
    phases.snap();
    phases.stitch();
    phases.result().seconds_snap = since(snap_start);
    guard_collapse(plan, phases); // stdout: before anything is streamed (files: before the commit)
    phases.write(plan, writer);
    return phases.finish();
}

RunResult snap_run(const SnapArgs& args, const Config& config, Progress& progress, Plan& plan, InterruptGuard& interrupt,
                   const StageOutputs& stage, const DeliverRun& deliver)
{
    if (args.input.empty() || args.output.empty()) {
        throw argument_error(std::string("missing ") + (args.input.empty() ? "IN" : "OUT") + ": trisnap snap IN OUT --tolerance T");
    }
    const RunBudget budget = choose_budget(args, config);
    WorkDir work = budget.on_disk ? WorkDir::on_disk(budget.work_dir, budget.resume) : WorkDir::in_memory();
    apply_gdal_budget(budget);
    const auto start = Clock::now();
    plan = make_plan(args, config);
    plan.write.index_boxes = index_boxes(budget.memory_limit);
    if (work.on_disk()) {
        plan.write.protected_files.refuse_tree(work.path(), "--work-dir");
    }
    work.bind(run_manifest(plan));
    const double open = since(start);
    CommitGroup outputs; // OUT and the report go into place together, or neither
    plan.write.commit_group = &outputs;
    RunResult result = run_pipeline(plan, work, budget, progress, interrupt);
    result.seconds_open = open;
    if (stage) {
        stage(outputs, plan, result);
    }
    commit_outputs(outputs, interrupt);
    plan.write.commit_group = nullptr;
    if (deliver) {
        try {
            deliver(plan, result);
        } catch (...) {
            work.finish(); // OUT is in place: the run is done, its work is of no more use
            throw;
        }
    }
    work.finish();
    result.problems.close();
    return result;
}

// Everything that changes the output, and the input's files as they are now: a work directory
// is continued only by the very same run.
std::string run_manifest(const Plan& plan)
{
    const SnapOptions& o = plan.options;
    const stitch::TilingOptions& t = plan.tiling;
    nlohmann::ordered_json m = {
        {"tool", "trisnap"},
        {"version", k_version},
        {"work_format", stitch::k_work_format},
        {"input", {{"path", plan.input_path}, {"files", input_files(plan)}, {"layer", layer_list(plan)},
                   {"where", plan.layer->GetAttrQueryString() ? plan.layer->GetAttrQueryString() : ""},
                   {"bbox", plan.bbox}}},
        {"snap", {{"tolerance", fmt::format("{:a}", o.tolerance)}, {"edge_separation", o.edge_separation},
                  {"sliver_factor", o.sliver_factor}, {"grid", o.grid}, {"max_drift_factor", o.max_drift_factor},
                  {"max_operations", o.max_operations}}},
        {"tiling", {{"single", t.plan.single}, {"size", t.plan.tile_size}, {"vertex_budget", t.plan.vertex_budget},
                    {"halo", t.halo_factor}, {"max_growth", t.max_growth},
                    {"on_error", t.on_error == stitch::OnError::skip ? "skip" : "stop"}}},
    };
    return m.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

} // namespace trisnap
