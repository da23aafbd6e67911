// `trisnap assess ORIGINAL SNAPPED (--tolerance T | --tolerance-m M) [--layer L | --layer-a A --layer-b B]
// [--key FIELD] [--report SNAP_REPORT.json] [--json FILE] [--fail-on-defects]`: measures a
// snapped layer against its original (any two OGR layers, so GEOS or CGAL output too); a table
// on stdout, the full report as JSON on request.
#include "app/command.hpp"
#include "app/layer_choice.hpp"
#include "assess/assess.hpp"
#include "assess/snap_report.hpp"
#include "config/errors.hpp"
#include "io/commit_group.hpp"
#include "io/dataset.hpp"
#include "io/tolerance.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <stdexcept>

namespace trisnap {
namespace {

class AssessCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("assess", "measure a snapped layer against its original");
        app->add_option("ORIGINAL", m_original, "the layer before snapping (any OGR vector dataset)")->required();
        app->add_option("SNAPPED", m_snapped, "the layer after snapping, by any tool")->required();
        app->add_option("--tolerance", m_tolerance, "the snapping tolerance T, in layer units");
        app->add_option("--tolerance-m", m_tolerance_m, "T in metres, converted on ORIGINAL as `snap` converts it");
        add_layer_choice_options(*app, m_layers, "ORIGINAL", "SNAPPED");
        app->add_option("--key", m_key, "match features by this field instead of by FID");
        app->add_option("--report", m_report, "the `trisnap snap --report` JSON of this run: the defects it explains are excused");
        app->add_option("--json", m_json, "write the full report, with examples, as JSON");
        app->add_flag("--fail-on-defects", m_fail_on_defects, "exit 3 when the contract does not hold");
        return app;
    }

    int run() override
    {
        setup_logging(0, 0);
        resolve_layer_choice(m_layers, m_original, m_snapped);
        GDALDatasetUniquePtr original = open_input(m_original);
        GDALDatasetUniquePtr snapped = open_input(m_snapped);
        OGRLayer& a = select_layer(*original, m_original, m_layers.layer_a);
        OGRLayer& b = select_layer(*snapped, m_snapped, m_layers.layer_b);
        const ProtectedFiles protect = protect_inputs(*original, *snapped);
        const std::optional<assess::SnapReport> report = read_report();
        AssessOptions options{tolerance(a, report), m_key, 20};
        options.report = report ? &*report : nullptr;
        const AssessReport result = measure({*original, a}, {*snapped, b}, options);
        if (!m_json.empty()) {
            write_text_file_atomically(m_json, assess_report_json(result), protect, "--json");
        }
        std::cout << assess_report_table(result);
        return m_fail_on_defects && !result.contract_holds() ? 3 : 0;
    }

private:
    std::optional<assess::SnapReport> read_report() const
    {
        if (m_report.empty()) {
            return std::nullopt;
        }
        return assess::read_snap_report(m_report);
    }

    /// --tolerance, --tolerance-m, else the snap report's.
    double tolerance(OGRLayer& layer, const std::optional<assess::SnapReport>& report) const
    {
        const std::optional<double> t = tolerance_option(m_tolerance, m_tolerance_m, layer);
        if (t) {
            return *t;
        }
        if (report && report->tolerance) {
            return *report->tolerance;
        }
        throw argument_error("no tolerance: give --tolerance T (layer units), --tolerance-m M or --report SNAP_REPORT.json");
    }

    static AssessReport measure(LayerSource a, LayerSource b, const AssessOptions& options)
    {
        try {
            return assess_layers(a, b, options);
        } catch (const std::invalid_argument& e) {
            throw argument_error(e.what());
        }
    }

    /// The files --json must never replace (every file of both layers' datasets and the snap
    /// report, under any name); --json is refused before measuring when it is one of them.
    ProtectedFiles protect_inputs(GDALDataset& original, GDALDataset& snapped) const
    {
        ProtectedFiles protect;
        protect.add_dataset(original, "ORIGINAL " + m_original);
        protect.add_dataset(snapped, "SNAPPED " + m_snapped);
        if (!m_report.empty()) {
            protect.add_file(m_report, "the report " + m_report);
        }
        if (!m_json.empty()) {
            check_text_file_target(m_json, protect, "--json");
        }
        return protect;
    }

    std::string m_original, m_snapped, m_key, m_json, m_report;
    LayerChoice m_layers;
    std::optional<double> m_tolerance;
    std::optional<double> m_tolerance_m;
    bool m_fail_on_defects = false;
};

} // namespace

std::unique_ptr<Command> make_assess_command() { return std::make_unique<AssessCommand>(); }

} // namespace trisnap
