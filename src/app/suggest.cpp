#include "app/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace trisnap {
namespace {

/// Optimal string alignment distance: insertions, deletions, substitutions and swaps of two
/// neighbouring characters each cost one ("sanp" is one edit from "snap").
std::size_t edit_distance(const std::string& a, const std::string& b)
{
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) {
        d[i][0] = i;
    }
    for (std::size_t j = 0; j <= b.size(); ++j) {
        d[0][j] = j;
    }
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            }
        }
    }
    return d[a.size()][b.size()];
}

std::vector<std::string> command_names(const CLI::App& app)
{
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
        names.push_back(sub->get_name());
    }
    return names;
}

std::vector<std::string> option_names(const CLI::App& command)
{
    std::vector<std::string> names;
    for (const CLI::Option* option : command.get_options()) {
        for (const std::string& name : option->get_lnames()) {
            names.push_back("--" + name);
        }
        for (const std::string& name : option->get_snames()) {
            names.push_back("-" + name);
        }
    }
    return names;
}

/// An argument written like an option: "-x", "--name", "--name=value", not "-", "-5" or "-.5".
bool looks_like_option(const std::string& arg)
{
    if (arg.size() < 2 || arg[0] != '-' || arg == "--") {
        return false;
    }
    return std::isdigit(static_cast<unsigned char>(arg[1])) == 0 && arg[1] != '.';
}

std::string join(const std::vector<std::string>& items)
{
    std::string out;
    for (const std::string& item : items) {
        out += (out.empty() ? "" : ", ") + item;
    }
    return out;
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates)
{
    const std::string best = closest_match(word, candidates);
    return best.empty() ? "" : "; did you mean " + best + "?";
}

/// The message for the first option `command` does not know, or "".
std::string unknown_option(const CLI::App& command, const std::vector<std::string>& args, std::size_t from)
{
    const std::vector<std::string> known = option_names(command);
    for (std::size_t i = from; i < args.size(); ++i) {
        if (!looks_like_option(args[i])) {
            continue;
        }
        const std::string name = args[i].substr(0, args[i].find('='));
        if (std::find(known.begin(), known.end(), name) == known.end()) {
            return "unknown option " + name + " for trisnap " + command.get_name() + did_you_mean(name, known) +
                   " (see trisnap " + command.get_name() + " --help)";
        }
    }
    return "";
}

} // namespace

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates)
{
    const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
    std::string best;
    std::size_t best_distance = limit + 1;
    for (const std::string& candidate : candidates) {
        const std::size_t d = edit_distance(word, candidate);
        if (d < best_distance) {
            best = candidate;
            best_distance = d;
        }
    }
    return best;
}

std::string explain_parse_error(const CLI::App& app, const std::vector<std::string>& args,
                                const CLI::ParseError& error)
{
    const std::vector<std::string> commands = command_names(app);
    for (std::size_t i = 1; i < args.size(); ++i) {
        if (looks_like_option(args[i])) {
            continue;
        }
        if (std::find(commands.begin(), commands.end(), args[i]) == commands.end()) {
            return "unknown command '" + args[i] + "'" + did_you_mean(args[i], commands) + " (commands: " +
                   join(commands) + ")";
        }
        const std::string message = unknown_option(*app.get_subcommand(args[i]), args, i + 1);
        if (!message.empty()) {
            return message;
        }
        break;
    }
    return std::string(error.what()) + " (see trisnap --help)";
}

} // namespace trisnap
