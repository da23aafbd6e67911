// `trisnap render IN [SNAPPED] -o OUT.svg|png [--bbox ...] [--worst N] [--tolerance T |
// --tolerance-m M] [--report REPORT.json]`: a picture of what snapping did (src/render), with
// the sites `trisnap assess` finds. setup() only parses; checks that need no I/O run first.
#include "app/command.hpp"
#include "app/layer_choice.hpp"
#include "app/options.hpp"
#include "config/errors.hpp"
#include "render/render.hpp"

#include <fmt/format.h>

#include <iostream>

namespace trisnap {
namespace {

class RenderCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("render", "draw a layer and its snapped output (SVG or PNG) with the worst sites marked");
        app->add_option("IN", m_options.input, "input vector dataset (drawn thin)")->required();
        app->add_option("SNAPPED", m_options.snapped, "snapped output of IN (drawn bold); without it IN is drawn alone");
        app->add_option("-o,--output", m_options.output, "picture to write: .svg or .png")->required();
        app->add_option("--bbox", m_bbox, "draw only xmin,ymin,xmax,ymax (layer units)");
        app->add_option("--worst", m_worst, "one zoomed panel for each of the N worst sites (needs a tolerance)");
        app->add_option("--tolerance", m_options.tolerance, "T in layer units: the sites are measured and ranked against it");
        app->add_option("--tolerance-m", m_options.tolerance_m, "T in metres, converted on IN as `snap` converts it");
        add_layer_choice_options(*app, m_layers, "IN", "SNAPPED");
        app->add_option("--key", m_options.key, "match features by this field (default: orig_fid of SNAPPED, else FID)");
        app->add_option("--width", m_options.width, "picture width in pixels (default 1200)");
        app->add_option("--report,--problems", m_options.report,
                        "a `trisnap snap --report` JSON: mark its problems, excuse what it explains (and take T from it)");
        return app;
    }

    int run() override
    {
        resolve_layer_choice(m_layers, m_options.input, m_options.snapped);
        m_options.layer_a = m_layers.layer_a;
        m_options.layer_b = m_layers.layer_b;
        if (m_bbox) {
            const std::vector<double> b = parse_bbox(*m_bbox);
            m_options.bbox = render::Box{b[0], b[1], b[2], b[3]};
        }
        if (m_worst) {
            if (*m_worst < 1 || *m_worst > 100) {
                throw argument_error(fmt::format("--worst must be 1..100, got {}", *m_worst));
            }
            m_options.worst = *m_worst;
        }
        const render::RenderResult result = render::render(m_options);
        std::cout << fmt::format("{}: {} x {} px, {}\n", m_options.output, result.width, result.height,
                                 result.panels ? fmt::format("{} panels", result.panels)
                                               : fmt::format("{} sites marked", result.shown.size()));
        std::cout << render::summarise(result);
        if (m_options.worst > 0 && result.panels < static_cast<std::size_t>(m_options.worst)) {
            std::cout << fmt::format("only {} distinct sites to show (asked for {})\n", result.panels, m_options.worst);
        }
        return 0;
    }

private:
    render::RenderOptions m_options;
    LayerChoice m_layers;
    std::optional<std::string> m_bbox; ///< given (even empty) or not
    std::optional<double> m_tolerance;
    std::optional<int> m_worst;
};

} // namespace

std::unique_ptr<Command> make_render_command() { return std::make_unique<RenderCommand>(); }

} // namespace trisnap
