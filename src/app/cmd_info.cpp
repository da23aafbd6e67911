// `trisnap info IN [--layer NAME]`: layers, geometry types, counts, CRS, extent, vertices, and a
// rough estimate of what a snap run would need.
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/text.hpp"
#include "io/dataset.hpp"
#include "io/layer_info.hpp"

#include <fmt/format.h>

#include <iostream>

namespace trisnap {
namespace {

void print_layer(const LayerInfo& info)
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
    const RunEstimate e = estimate_run(info.vertices, info.features);
    std::cout << fmt::format("  snap:     ~{:.0f} MB, ~{:.1f} s in one triangulation (rough estimate)\n",
                             e.memory_mb, e.seconds);
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
        for (const LayerInfo& info : infos) print_layer(info);
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
