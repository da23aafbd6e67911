#include "app/layer_choice.hpp"

#include "config/errors.hpp"
#include "io/dataset.hpp"

namespace trisnap {
namespace {

/// The file must have `name`: with --layer, a file without it is an ambiguity, not a typo.
void require_layer(const std::string& path, const std::string& role, const std::string& name)
{
    GDALDatasetUniquePtr dataset = open_input(path);
    if (dataset->GetLayerByName(name.c_str()) != nullptr) {
        return;
    }
    throw argument_error("--layer " + name + ": " + role + " " + path + " has no layer of that name (layers: " +
                         list_layers(*dataset) + "); name each file's layer with --layer-a and --layer-b");
}

} // namespace

void add_layer_choice_options(CLI::App& command, LayerChoice& layers, const std::string& first, const std::string& second)
{
    layers.first = first;
    layers.second = second;
    command.add_option("--layer", layers.flag, "the layer of both files, when they name it alike (as snap keeps it)");
    command.add_option("--layer-a", layers.layer_a, "layer of " + first + " (default: its only polygon/line layer)");
    command.add_option("--layer-b", layers.layer_b, "layer of " + second + " (default: its only polygon/line layer)");
}

void resolve_layer_choice(LayerChoice& layers, const std::string& path_a, const std::string& path_b)
{
    if (layers.flag.empty()) {
        return;
    }
    if (!layers.layer_a.empty() || !layers.layer_b.empty()) {
        throw argument_error("--layer " + layers.flag + " names the layer of both files; give it alone, or "
                             "--layer-a and --layer-b");
    }
    require_layer(path_a, layers.first, layers.flag);
    layers.layer_a = layers.flag;
    if (!path_b.empty()) {
        require_layer(path_b, layers.second, layers.flag);
        layers.layer_b = layers.flag;
    }
}

} // namespace trisnap
