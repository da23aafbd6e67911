// `trisnap assess ORIGINAL SNAPPED --tolerance T [--layer-a A] [--layer-b B] [--key FIELD]
// [--json FILE] [--fail-on-defects]`: measures a snapped layer against its original (any two OGR
// layers, so GEOS or CGAL output too); a table on stdout, the full report as JSON on request.
#include "app/command.hpp"
#include "assess/assess.hpp"
#include "config/errors.hpp"
#include "io/dataset.hpp"
#include "io/io_error.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iostream>
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
        app->add_option("--tolerance", m_tolerance, "the snapping tolerance T, in layer units")->required();
        app->add_option("--layer-a", m_layer_a, "layer of ORIGINAL (default: its only polygon/line layer)");
        app->add_option("--layer-b", m_layer_b, "layer of SNAPPED (default: its only polygon/line layer)");
        app->add_option("--key", m_key, "match features by this field instead of by FID");
        app->add_option("--json", m_json, "write the full report, with examples, as JSON");
        app->add_flag("--fail-on-defects", m_fail_on_defects, "exit 3 when the contract does not hold");
        return app;
    }

    int run() override
    {
        setup_logging(0, 0);
        if (!std::isfinite(m_tolerance) || m_tolerance <= 0)
            throw argument_error(fmt::format("--tolerance must be finite and > 0, got {}", m_tolerance));
        GDALDatasetUniquePtr original = open_input(m_original);
        GDALDatasetUniquePtr snapped = open_input(m_snapped);
        OGRLayer& a = select_layer(*original, m_original, m_layer_a);
        OGRLayer& b = select_layer(*snapped, m_snapped, m_layer_b);
        AssessReport report;
        try {
            report = assess_layers(a, b, AssessOptions{m_tolerance, m_key, 20});
        } catch (const std::invalid_argument& e) {
            throw argument_error(e.what());
        }
        if (!m_json.empty()) write_json(report);
        std::cout << assess_report_table(report);
        return m_fail_on_defects && !report.contract_holds() ? 3 : 0;
    }

private:
    void write_json(const AssessReport& report) const
    {
        std::ofstream out(m_json);
        out << assess_report_json(report);
        if (!out.flush()) throw io_error(m_json, "", "cannot write the JSON report");
    }

    std::string m_original, m_snapped, m_layer_a, m_layer_b, m_key, m_json;
    double m_tolerance = 0;
    bool m_fail_on_defects = false;
};

} // namespace

std::unique_ptr<Command> make_assess_command() { return std::make_unique<AssessCommand>(); }

} // namespace trisnap
