// `trisnap validate IN OUT ...`: the dry run. Opens the input, checks every option and the
// output path, reads the input once as snap's read phase does (also an .osm.pbf) and stops
// where that phase would (nothing matches --where/--bbox, the collapse guard's pre-check), prints
// the plan and the estimate, and writes nothing.
#include "app/budget.hpp"
#include "app/collapse_guard.hpp"
#include "app/command.hpp"
#include "app/estimate.hpp"
#include "app/options.hpp"
#include "app/phases.hpp"
#include "app/plan.hpp"

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
        const InputSurvey survey = survey_input(plan);
        check_read(plan, survey.total(), survey.smaller); // where snap's read phase would stop
        count_features(plan, survey);
        print_plan(plan, std::cout);
        print_estimate(plan, config, survey);
        print_budget(m_args, config);
        std::cout << fmt::format("collapse:  at least {} of {} features vanish (smaller than the tolerance)\n",
                                 survey.smaller, survey.total());
        std::cout << "validate: ok, nothing written\n";
        return 0;
    }

private:
    /// The counts the plan could not know without a read (OSM), as the read found them.
    static void count_features(Plan& plan, const InputSurvey& survey)
    {
        plan.feature_counts.assign(survey.features.begin(), survey.features.end());
        plan.feature_count = static_cast<std::int64_t>(survey.total());
    }

    /// The run's estimate (app/estimate.hpp) from the layers' vertices after the filters, as
    /// `trisnap info` counts them (an .osm.pbf is read too, through the same reader as snap's).
    static void print_estimate(Plan& plan, const Config& config, const InputSurvey& survey)
    {
        const EstimateSettings settings = estimate_settings(config);
        const RunEstimate e = estimate_run(estimate_input(plan.input_path, static_cast<std::int64_t>(survey.vertices),
                                                          plan.feature_count),
                                           settings);
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

    SnapArgs m_args;
};

} // namespace

std::unique_ptr<Command> make_validate_command() { return std::make_unique<ValidateCommand>(); }

} // namespace trisnap
