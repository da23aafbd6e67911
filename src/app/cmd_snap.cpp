// `trisnap snap IN OUT --tolerance T ...`: the whole layer through one engine call.
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "app/report.hpp"
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
        if (!resolved) return 0;
        const Config& config = *resolved;
        const ThreadLimit limit(config.run.threads);
        const auto start = std::chrono::steady_clock::now();
        Progress progress(m_args.progress, m_args.json_progress);
        Plan plan = make_plan(m_args, config); // also checks the report path
        CommitGroup outputs; // OUT and the report are renamed into place together, or neither
        plan.write.commit_group = &outputs;
        const RunResult result = run_pipeline(plan, progress);
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!m_args.report.empty()) {
            stage_report(outputs, m_args.report, plan, result, total);
        }
        outputs.commit();
        if (m_args.quiet == 0) print_summary(std::cout, plan, result, total);
        return m_args.strict && !result.problems.empty() ? 3 : 0;
    }

private:
    SnapArgs m_args;
};

} // namespace

std::unique_ptr<Command> make_snap_command() { return std::make_unique<SnapCommand>(); }

} // namespace trisnap
