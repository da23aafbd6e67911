// `trisnap validate IN OUT ...`: the dry run. Opens the input, checks every option and the
// output path, prints the plan, and writes nothing.
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/plan.hpp"
#include "io/layer_info.hpp"

#include <fmt/format.h>

#include <iostream>

namespace trisnap {
namespace {

class ValidateCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("validate", "check a snap command and print its plan; writes nothing");
        add_snap_options(*app, m_args, false);
        return app;
    }

    int run() override
    {
        const std::optional<Config> resolved = start_snap_command(m_args);
        if (!resolved) return 0;
        const Config& config = *resolved;
        Plan plan = make_plan(m_args, config);
        print_plan(plan, std::cout);
        if (plan.feature_count >= 0) {
            // Vertices are not known without a read; ~15 per feature is typical of OSM areas.
            const RunEstimate e = estimate_run(plan.feature_count * 15, plan.feature_count);
            std::cout << fmt::format("estimate:  ~{:.0f} MB, ~{:.1f} s (rough; `trisnap info` counts vertices)\n",
                                     e.memory_mb, e.seconds);
        }
        std::cout << "validate: ok, nothing written\n";
        return 0;
    }

private:
    SnapArgs m_args;
};

} // namespace

std::unique_ptr<Command> make_validate_command() { return std::make_unique<ValidateCommand>(); }

} // namespace trisnap
