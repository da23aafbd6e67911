// `trisnap snap IN OUT --tolerance T ...`: read, tile, snap, stitch and write one layer, in
// memory or out of core under a memory limit (app/budget.hpp, app/pipeline.hpp).
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "app/report.hpp"
#include "config/errors.hpp"
#include "io/output_driver.hpp"
#include "io/problems_layer.hpp"
#include "io/commit_group.hpp"

#include <chrono>
#include <iostream>

namespace trisnap {
namespace {

class SnapCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("snap", "snap-round a polygon/line layer and write the result");
        add_snap_options(*app, m_args, true);
        return app;
    }

    int run() override
    {
        const std::optional<Config> resolved = start_snap_command(m_args);
        if (!resolved) {
            return 0;
        }
        const Config& config = *resolved;
        const ThreadLimit limit(config.run.threads);
        const auto start = std::chrono::steady_clock::now();
        InterruptGuard interrupt; // from here to the end: no moment of the run gets a signal's default action
        Progress progress(m_args.progress, m_args.json_progress);
        Plan plan;
        double total = 0;
        int code = 0;
        const auto stage = [&](CommitGroup& outputs, const Plan& p, const RunResult& r) {
            total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (!m_args.report.empty()) {
                stage_report(outputs, m_args.report, p, r, total);
            }
        };
        const auto deliver = [&](const Plan& p, const RunResult& r) { code = deliver_run(m_args, p, r, total); };
        snap_run(m_args, config, progress, plan, interrupt, stage, deliver);
        interrupt.warn_if_too_late();
        return code;
    }

private:
    SnapArgs m_args;
};

} // namespace

int deliver_run(const SnapArgs& args, const Plan& plan, const RunResult& result, double total_seconds)
{
    if (!args.problems_layer.empty()) {
        const bool update = args.overwrite || args.update || args.append;
        std::vector<std::string> names; // several layers: each problem says whose FID it carries
        for (std::size_t k = 0; plan.layers.size() > 1 && k < plan.layers.size(); ++k) {
            names.push_back(plan.layers[k]->GetName());
        }
        const ProblemSource problems = [&](const std::function<void(const Problem&)>& f) { result.problems.for_each(f); };
        write_problems_layer(args.problems_layer, problems, plan.layer->GetSpatialRef(), update, names);
    }
    if (args.quiet == 0) {
        print_summary(is_stdout_path(plan.write.path) ? std::cerr : std::cout, plan, result, total_seconds);
    }
    return args.strict && !result.problems.empty() ? 3 : 0;
}

std::unique_ptr<Command> make_snap_command() { return std::make_unique<SnapCommand>(); }

} // namespace trisnap
