#pragma once
// The layers `assess` and `render` compare: --layer-a (of the original) and --layer-b (of the
// snapped file), or --layer NAME for both when both files have a layer of that name (snap
// keeps the name, so that is the usual case). Checked before any feature is read.
#include <CLI/CLI.hpp>

#include <string>

namespace trisnap {

struct LayerChoice {
    std::string flag;    ///< --layer NAME (both files)
    std::string layer_a; ///< --layer-a: the first file's
    std::string layer_b; ///< --layer-b: the second file's
    std::string first;   ///< what the files are called in --help ("ORIGINAL", "SNAPPED")
    std::string second;
};

/// Declares --layer, --layer-a and --layer-b on `command`; `first` and `second` name the files.
void add_layer_choice_options(CLI::App& command, LayerChoice& layers, const std::string& first, const std::string& second);

/// Resolves --layer into layer_a and layer_b. Throws argument_error when --layer comes with
/// --layer-a or --layer-b, or when a file (`path_b` may be "": no second file) has no layer of
/// that name, naming its layers and the two flags that say which is which.
void resolve_layer_choice(LayerChoice& layers, const std::string& path_a, const std::string& path_b);

} // namespace trisnap
