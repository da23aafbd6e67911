#include "app/suggest.hpp"

#include <algorithm>
#include <cctype>
#include <map>

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

constexpr const char* k_reproject = "trisnap does not reproject: it snaps in the layer's CRS and writes that CRS "
                                    "(reprojecting after snapping would undo the separations); reproject with "
                                    "ogr2ogr first, then snap";

/// ogr2ogr options that do something trisnap does not: what to do instead. Edit distance alone
/// pointed -sql at -q and -nlt at --nln.
const std::map<std::string, std::string>& ogr2ogr_only()
{
    static const std::map<std::string, std::string> options = {
        {"-t_srs", k_reproject},
        {"-s_srs", k_reproject},
        {"-a_srs", "trisnap does not assign a CRS: it writes the layer's own; assign one with ogr2ogr -a_srs first, "
                   "then snap"},
        {"-clipsrc", "trisnap does not clip: --bbox (-spat) selects the features that meet a box, whole; clip "
                     "with ogr2ogr first, then snap"},
        {"-clipdst", "trisnap does not clip: --bbox (-spat) selects the features that meet a box, whole; clip "
                     "with ogr2ogr first, then snap"},
        {"-sql", "trisnap reads a layer, not an SQL result: choose features with --where (-where) and fields with "
                 "--select (-select), or run ogr2ogr -sql first"},
        {"-dialect", "trisnap reads a layer, not an SQL result: --where (-where) takes OGR SQL"},
        {"-nlt", "trisnap keeps the input's geometry types (it snaps polygons and lines as they are); convert the "
                 "output with ogr2ogr -nlt if you need to (that moves no vertex)"},
        {"-preserve_fid", "FIDs are kept where the format stores them, else in the field orig_fid"},
        {"-makevalid", "trisnap's polygons are valid by construction; invalid input is repaired and reported"},
    };
    return options;
}

/// The shortest candidate that `word` begins (`--tol` is --tolerance), for words of at least
/// three letters after the dashes; "" when none.
std::string completion(const std::string& word, const std::vector<std::string>& candidates)
{
    const std::size_t letters = word.find_first_not_of('-');
    if (letters == std::string::npos || word.size() - letters < 3) {
        return "";
    }
    std::string best;
    for (const std::string& c : candidates) {
        if (c.size() > word.size() && c.compare(0, word.size(), word) == 0 && (best.empty() || c.size() < best.size())) {
            best = c;
        }
    }
    return best;
}

std::string option_hint(const std::string& name, const std::vector<std::string>& known)
{
    if (const auto it = ogr2ogr_only().find(name); it != ogr2ogr_only().end()) {
        return ": " + it->second;
    }
    const std::string begun = completion(name, known);
    return begun.empty() ? did_you_mean(name, known) : "; did you mean " + begun + "?";
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
            return "unknown option " + name + " for trisnap " + command.get_name() + option_hint(name, known) +
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
