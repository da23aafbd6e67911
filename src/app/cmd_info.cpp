// `trisnap info IN [--layer NAME]`: layers, geometry types, counts, CRS, extent, vertices, and a
// estimate of what a snap run would need (app/estimate.hpp).
#include "app/command.hpp"
#include "app/estimate.hpp"
#include "app/options.hpp"
#include "app/text.hpp"
#include "io/dataset.hpp"
#include "io/layer_info.hpp"

#include <fmt/format.h>

#include <iostream>

namespace trisnap {
namespace {

// What `trisnap snap IN OUT --layer NAME` would need with the default settings, and --no-tiles.
void print_estimates(const std::string& input, const LayerInfo& info)
{
    const EstimateInput in = estimate_input(input, info.vertices, info.features);
    EstimateSettings settings = estimate_settings(Config{});
    std::cout << fmt::format("  snap:     {}\n", describe_estimate(estimate_run(in, settings), settings));
    settings.tiled = false;
    std::cout << fmt::format("            {}\n", describe_estimate(estimate_run(in, settings), settings));
}

void print_layer(const std::string& input, const LayerInfo& info)
{
    std::cout << fmt::format("layer '{}': {}, {}, {}\n", info.name, info.declared_type,
                             count_of(info.features, "feature"), count_of(info.vertices, "vertex", "vertices"));
    std::cout << fmt::format("  crs:      {}{}\n", info.crs, info.geographic ? ", geographic (degrees)" : "");
    if (info.has_extent)
        std::cout << fmt::format("  extent:   {:.9g}, {:.9g}, {:.9g}, {:.9g}\n", info.extent[0], info.extent[1],
                                 info.extent[2], info.extent[3]);
    std::string types;
    for (const auto& [type, n] : info.types) types += fmt::format("{}{} {}", types.empty() ? "" : ", ", type, n);
    std::cout << fmt::format("  types:    {}\n", types.empty() ? "none" : types);
    std::cout << fmt::format("  fields:   {}{}\n", info.fields,
                             info.fid_column.empty() ? "" : ", FID column " + info.fid_column);
    if (!is_snappable_layer_type(info.geometry_type)) return;
    print_estimates(input, info);
}

class InfoCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        CLI::App* app = parent.add_subcommand("info", "describe the layers of a vector dataset");
        app->add_option("IN", m_input, "input vector dataset")->required();
        app->add_option("--layer", m_layer, "describe only this layer");
        app->add_option("--oo", m_open_options, "input open option K=V (repeatable), as ogrinfo -oo");
        return app;
    }

    int run() override
    {
        setup_logging(0, 0);
        check_key_values(m_open_options, "--oo");
        GDALDatasetUniquePtr dataset = open_input(m_input, m_open_options);
        OGRLayer* only = m_layer.empty() ? nullptr : &find_layer(*dataset, m_input, m_layer);
        const std::vector<LayerInfo> infos = scan_layers(*dataset, only); // may throw: print after
        std::cout << fmt::format("{} ({}), {}\n", m_input, dataset->GetDriverName(),
                                 count_of(dataset->GetLayerCount(), "layer"));
        for (const LayerInfo& info : infos) print_layer(m_input, info);
        return 0;
    }

private:
    std::string m_input;
    std::string m_layer;
    std::vector<std::string> m_open_options;
};

} // namespace

std::unique_ptr<Command> make_info_command() { return std::make_unique<InfoCommand>(); }

} // namespace trisnap
