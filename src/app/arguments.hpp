#pragma once
// The command line before CLI11 sees it: ogr2ogr's one-dash spellings (-nln, -lco, -dsco, -oo,
// -where, -spat, -select, -overwrite, -progress, -skipfailures) become ours, and GDAL's
// `--config KEY VALUE` is taken out and applied with CPLSetConfigOption. `--config FILE.toml`
// (an existing file, or a name ending in .toml) still means our settings file (--settings).
#include <string>
#include <utility>
#include <vector>

namespace trisnap {

struct Arguments {
    std::vector<std::string> argv;                                ///< what CLI11 parses
    std::vector<std::pair<std::string, std::string>> gdal_config; ///< --config KEY VALUE, in order
};

/// Rewrites argv as described above. Throws argument_error for a --config or -spat that lacks
/// its values.
Arguments normalise_arguments(int argc, char** argv);

/// CPLSetConfigOption for every --config KEY VALUE (before GDALAllRegister, as GDAL's tools do).
void apply_gdal_config(const Arguments& arguments);

} // namespace trisnap
