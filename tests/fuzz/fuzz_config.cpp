// Fuzz target: arbitrary bytes as a TOML config (src/config). The loader may only throw
// config_error; a config it accepts and check_config() passes must print (to_toml, what
// --print-config shows) as TOML that loads back to the same configuration.
#include "config/config.hpp"
#include "config/errors.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    trisnap::Config config = trisnap::default_config();
    try {
        trisnap::load_config_text(text, "fuzz.toml", config);
    } catch (const trisnap::config_error&) {
        return 0;
    }
    if (!trisnap::check_config(config).empty()) {
        return 0;
    }
    const std::string printed = trisnap::to_toml(config);
    trisnap::Config again = trisnap::default_config();
    try {
        trisnap::load_config_text(printed, "printed.toml", again);
    } catch (const trisnap::config_error& e) {
        std::fprintf(stderr, "fuzz_config: printed config does not load: %s\n%s", e.what(), printed.c_str());
        std::abort();
    }
    if (trisnap::to_toml(again) != printed) {
        std::fprintf(stderr, "fuzz_config: printed config reads back differently:\n%s---\n%s", printed.c_str(),
                     trisnap::to_toml(again).c_str());
        std::abort();
    }
    return 0;
}
