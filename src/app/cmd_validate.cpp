// `trisnap validate IN OUT ...`: the dry run. Opens the input, checks every option and the
// output path, prints the plan, and writes nothing.
#include "app/budget.hpp"
#include "app/collapse_guard.hpp"
#include "app/command.hpp"
#include "app/estimate.hpp"
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
        print_estimate(plan, config);
        print_budget(m_args, config);
        predict_collapse(plan);
        std::cout << "validate: ok, nothing written\n";
        return 0;
    }

private:
    /// The run's estimate (app/estimate.hpp) from the layer's vertices after the filters, as
    /// `trisnap info` prints it. An .osm.pbf is not read (it would take the run's whole read):
    /// its vertices are bounded from the file's size.
    static void print_estimate(Plan& plan, const Config& config)
    {
        std::int64_t vertices = -1;
        std::int64_t features = -1;
        if (plan.feature_count >= 0) {
            vertices = 0;
            features = 0;
            for (OGRLayer* layer : plan.layers) { // several layers are one engine run
                const LayerInfo counted = scan_layers(*plan.dataset, layer).at(0);
                vertices += counted.vertices;
                features += counted.features;
            }
        }
        const EstimateSettings settings = estimate_settings(config);
        const RunEstimate e = estimate_run(estimate_input(plan.input_path, vertices, features), settings);
        std::cout << fmt::format("estimate:  {}\n", describe_estimate(e, settings));
    }

    /// In memory or out of core, as `snap` decides before it opens the input (the report's
    /// memory.estimate_bytes).
    static void print_budget(const SnapArgs& args, const Config& config)
    {
        const RunBudget b = choose_budget(args, config);
        std::cout << fmt::format("memory:    {} ({}; {} bytes before the input is opened)\n",
                                 b.on_disk ? "out of core" : "in memory", b.reason, b.estimate);
    }

    /// Features smaller than the tolerance vanish when snapped: a run the collapse guard would
    /// stop fails here already (exit 2). Not for inputs whose count needs a full read (OSM).
    static void predict_collapse(const Plan& plan)
    {
        if (plan.feature_count < 0) {
            return;
        }
        std::size_t small = 0;
        for (OGRLayer* layer : plan.layers) {
            small += count_smaller_than(*layer, plan.tolerance);
        }
        const auto features = static_cast<std::size_t>(plan.feature_count);
        check_collapse(plan, Drops{small, 0}, features, true);
        std::cout << fmt::format("collapse:  at least {} of {} features vanish (smaller than the tolerance)\n",
                                 small, features);
    }

    SnapArgs m_args;
};

} // namespace

std::unique_ptr<Command> make_validate_command() { return std::make_unique<ValidateCommand>(); }

} // namespace trisnap
