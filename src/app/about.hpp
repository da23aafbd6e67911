#pragma once
// What the top-level flags print: --version (with the libraries it runs with), --formats, and
// the hidden --help-man and --completion-bash that the build turns into the man page and the
// bash completion file (so both come from the same text as --help).
#include <CLI/CLI.hpp>

#include <string>

namespace trisnap {

/// "trisnap 0.1.0" and a line per library: GDAL, PROJ and GEOS as loaded, CGAL as compiled
/// in (header-only), oneTBB as loaded.
std::string version_text();

/// The vector drivers of this GDAL build: which read, which write, which stream to stdout.
std::string formats_text();

/// The man page (roff) for `app` and its subcommands, from their help texts.
std::string man_page(const CLI::App& app);

/// A bash completion script for `app`: subcommands, then each one's options, then files.
std::string bash_completion(const CLI::App& app);

/// Adds --version, --formats, --help-man and --completion-bash to `app`; each prints and ends
/// the parse with CLI::Success.
void add_global_flags(CLI::App& app);

} // namespace trisnap
