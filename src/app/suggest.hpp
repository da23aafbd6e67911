#pragma once
// "Did you mean ...?" for a mistyped subcommand or option, from the names CLI11 knows.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace trisnap {

/// The candidate nearest to `word` in edit distance (a swap of two neighbours counts one), or ""
/// when none is near enough to be a typo (at most 2 edits, or a third of the word's length).
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

/// A one-line message for a failed parse of `args` (argv after normalisation): an unknown
/// command or option with the nearest valid one named; otherwise CLI11's own message.
std::string explain_parse_error(const CLI::App& app, const std::vector<std::string>& args,
                                const CLI::ParseError& error);

} // namespace trisnap
