#include "config/config.hpp"

#include "config/errors.hpp"
#include "config/size.hpp"
#include "core/snap.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace trisnap {

namespace {

/// Larger than any real config; bounds what a wrong --config (a data file, a pipe) costs.
constexpr std::size_t k_max_config_bytes = 1 << 20;

/// 2^20: with t <= k_max_tolerance and 10 doublings, a halo stays below 2^510.
constexpr double k_max_halo = 1048576.0;

std::string config_message(const std::string& file, long line, const std::string& key, const std::string& reason)
{
    std::string out = file;
    if (line > 0) out.append(":").append(std::to_string(line));
    out.append(": ");
    if (!key.empty()) out.append("key '").append(key).append("': ");
    return out.append(reason);
}

} // namespace

config_error::config_error(const std::string& file, long line, const std::string& key,
                           const std::string& reason)
    : std::runtime_error(config_message(file, line, key, reason)), m_file(file), m_line(line), m_key(key)
{
}

namespace {

/// Reads one TOML value into the config; returns "" when it was set, else why not (wrong type,
/// an integer that does not fit the field).
using Setter = std::function<std::string(const toml::node&, Config&)>;

struct KeySpec {
    const char* section;
    const char* name;
    Setter set;
};

constexpr const char* k_wrong_type = "wrong type for this key";

template <typename Field>
std::string set_integer(const toml::node& n, Field& target)
{
    auto v = n.as_integer();
    if (!v) {
        return k_wrong_type;
    }
    // TOML integers are 64-bit: a value that does not fit the field must not wrap (threads =
    // 4294967297 would become 1).
    if (!std::in_range<Field>(v->get())) {
        return std::to_string(v->get()) + " is out of range [" + std::to_string(std::numeric_limits<Field>::min()) +
               ", " + std::to_string(std::numeric_limits<Field>::max()) + "]";
    }
    target = static_cast<Field>(v->get());
    return "";
}

// One key's setter: a float (integers accepted), an integer or a boolean from the TOML node into
// `field` of `section`.
template <typename Section, typename Field>
Setter set(Section Config::*section, Field Section::*field)
{
    return [section, field](const toml::node& n, Config& c) -> std::string {
        Field& target = (c.*section).*field;
        if constexpr (std::is_same_v<Field, bool>) {
            auto v = n.as_boolean();
            if (!v) {
                return k_wrong_type;
            }
            target = v->get();
            return "";
        } else if constexpr (std::is_integral_v<Field>) {
            return set_integer(n, target);
        } else {
            auto v = n.value<double>();
            if (!v) {
                return k_wrong_type;
            }
            target = *v;
            return "";
        }
    };
}

// A size: "2GiB" (see config/size.hpp) or a number of bytes. A bad size throws (the caller
// names file, line and key).
template <typename Section>
Setter set_size(Section Config::*section, std::uint64_t Section::*field)
{
    return [section, field](const toml::node& n, Config& c) -> std::string {
        std::uint64_t& target = (c.*section).*field;
        if (auto text = n.value<std::string>()) {
            try {
                target = parse_size(*text, "size");
            } catch (const argument_error& e) {
                return e.what();
            }
            return "";
        }
        if (auto v = n.as_integer(); v && v->get() > 0) {
            target = static_cast<std::uint64_t>(v->get());
            return "";
        }
        return "expected a size such as \"2GiB\" or a number of bytes > 0";
    };
}

// One of a few words.
template <typename Section>
Setter set_choice(Section Config::*section, std::string Section::*field, std::vector<std::string> allowed)
{
    return [section, field, allowed](const toml::node& n, Config& c) -> std::string {
        auto text = n.value<std::string>();
        if (!text) {
            return k_wrong_type;
        }
        if (std::find(allowed.begin(), allowed.end(), *text) == allowed.end()) {
            std::string list;
            for (const std::string& a : allowed) list += (list.empty() ? "" : " or ") + ("\"" + a + "\"");
            return "expected " + list + ", got \"" + *text + "\"";
        }
        (c.*section).*field = *text;
        return "";
    };
}

const std::vector<KeySpec>& key_specs()
{
    static const std::vector<KeySpec> specs{
        {"snap", "tolerance", set(&Config::snap, &SnapConfig::tolerance)},
        {"snap", "tolerance_m", set(&Config::snap, &SnapConfig::tolerance_m)},
        {"snap", "edge_separation", set(&Config::snap, &SnapConfig::edge_separation)},
        {"snap", "sliver_factor", set(&Config::snap, &SnapConfig::sliver_factor)},
        {"snap", "grid", set(&Config::snap, &SnapConfig::grid)},
        {"snap", "max_drift_factor", set(&Config::snap, &SnapConfig::max_drift_factor)},
        {"snap", "max_operations", set(&Config::snap, &SnapConfig::max_operations)},
        {"tiling", "size", set(&Config::tiling, &TilingConfig::size)},
        {"tiling", "vertex_budget", set(&Config::tiling, &TilingConfig::vertex_budget)},
        {"tiling", "halo", set(&Config::tiling, &TilingConfig::halo)},
        {"tiling", "max_growth", set(&Config::tiling, &TilingConfig::max_growth)},
        {"tiling", "no_tiles", set(&Config::tiling, &TilingConfig::no_tiles)},
        {"run", "threads", set(&Config::run, &RunConfig::threads)},
        {"run", "memory_limit", set_size(&Config::run, &RunConfig::memory_limit)},
        {"run", "allow_collapse", set(&Config::run, &RunConfig::allow_collapse)},
        {"run", "on_error", set_choice(&Config::run, &RunConfig::on_error, {"stop", "skip"})},
    };
    return specs;
}

const KeySpec* find_spec(std::string_view section, std::string_view name)
{
    for (const auto& spec : key_specs())
        if (section == spec.section && name == spec.name) return &spec;
    return nullptr;
}

std::string num(double v)
{
    std::ostringstream out;
    out << v;
    return out.str();
}

/// Shortest text that reads back as the same double, always with a '.' or exponent (TOML float).
std::string toml_float(double v)
{
    char buffer[64];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
    std::string text(buffer, end);
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
    return text;
}

long line_of(const toml::node& node) { return static_cast<long>(node.source().begin.line); }

void load_section(const std::string& path, const std::string& section, const toml::table& table,
                  Config& config)
{
    for (auto&& [key, node] : table) {
        const std::string full = section + "." + std::string(key.str());
        const KeySpec* spec = find_spec(section, key.str());
        if (!spec) throw config_error(path, line_of(node), full, "unknown key");
        if (const std::string reason = spec->set(node, config); !reason.empty()) {
            throw config_error(path, line_of(node), full, reason);
        }
    }
}

toml::table parse_toml(std::string_view text, const std::string& path)
{
    try {
        return toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        throw config_error(path, static_cast<long>(e.source().begin.line), "",
                           std::string(e.description()));
    }
}

/// Why `path` cannot be a config file ("" when it may be): it must exist and be a regular file
/// or a pipe; a directory or a device (/dev/zero) would otherwise read as an empty config.
std::string unusable_file(const std::string& path)
{
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (st.type() == std::filesystem::file_type::not_found) {
        return "no such file";
    }
    if (ec) {
        return "cannot read: " + ec.message();
    }
    if (st.type() == std::filesystem::file_type::directory) {
        return "is a directory, not a TOML file";
    }
    if (st.type() != std::filesystem::file_type::regular && st.type() != std::filesystem::file_type::fifo) {
        return "not a regular file (a device or socket), not a TOML file";
    }
    return "";
}

/// The whole file, at most k_max_config_bytes; throws config_error when it cannot be read.
std::string read_config_text(const std::string& path)
{
    if (const std::string reason = unusable_file(path); !reason.empty()) {
        throw config_error(path, 0, "", reason);
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw config_error(path, 0, "", std::string("cannot read: ") + std::strerror(errno));
    }
    std::string text(k_max_config_bytes + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    if (in.bad()) {
        throw config_error(path, 0, "", std::string("cannot read: ") + std::strerror(errno));
    }
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (text.size() > k_max_config_bytes) {
        throw config_error(path, 0, "", "larger than 1 MiB, not a config file");
    }
    return text;
}

} // namespace

Config default_config()
{
    const SnapOptions engine{};
    Config config;
    config.snap.edge_separation = engine.edge_separation;
    config.snap.sliver_factor = engine.sliver_factor;
    config.snap.grid = engine.grid;
    config.snap.max_drift_factor = engine.max_drift_factor;
    config.snap.max_operations = static_cast<std::int64_t>(engine.max_operations);
    return config;
}

void load_config_file(const std::string& path, Config& config)
{
    load_config_text(read_config_text(path), path, config);
}

void load_config_text(std::string_view text, const std::string& path, Config& config)
{
    if (text.find('\0') != std::string_view::npos) {
        throw config_error(path, 0, "", "contains a NUL byte, not a TOML text file");
    }
    // Debian's toml++ 3.3 reaches an "unreachable" branch (undefined behaviour) on some non-ASCII
    // characters, in keys and elsewhere (found by fuzz_config: "0\u01a4AA", a key "snapl\u00e9rance"):
    // every key is ASCII, so the whole file must be.
    const auto non_ascii = std::find_if(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x80; });
    if (non_ascii != text.end()) {
        const long line = 1 + static_cast<long>(std::count(text.begin(), non_ascii, '\n'));
        throw config_error(path, line, "", "non-ASCII character: config files must be ASCII");
    }
    const toml::table root = parse_toml(text, path);
    for (auto&& [key, node] : root) {
        const std::string section(key.str());
        const bool known = section == "snap" || section == "run" || section == "tiling";
        if (!known || !node.is_table())
            throw config_error(path, line_of(node), section,
                               known ? "must be a table" : "unknown section (expected [snap], [tiling] or [run])");
        load_section(path, section, *node.as_table(), config);
    }
}

std::string to_toml(const Config& config)
{
    const SnapConfig& s = config.snap;
    std::string out = "[snap]\n";
    if (s.tolerance) out += "tolerance = " + toml_float(*s.tolerance) + "\n";
    if (s.tolerance_m) out += "tolerance_m = " + toml_float(*s.tolerance_m) + "\n";
    out += "edge_separation = " + toml_float(s.edge_separation) + "\n";
    out += "sliver_factor = " + toml_float(s.sliver_factor) + "\n";
    out += "grid = " + toml_float(s.grid) + "\n";
    out += "max_drift_factor = " + toml_float(s.max_drift_factor) + "\n";
    out += "max_operations = " + std::to_string(s.max_operations) + "\n";
    const TilingConfig& t = config.tiling;
    out += "\n[tiling]\nsize = " + toml_float(t.size) + "\nvertex_budget = " + std::to_string(t.vertex_budget) +
           "\nhalo = " + toml_float(t.halo) + "\nmax_growth = " + std::to_string(t.max_growth) +
           "\nno_tiles = " + (t.no_tiles ? "true" : "false") + "\n";
    out += "\n[run]\nthreads = " + std::to_string(config.run.threads) + "\n";
    if (config.run.memory_limit > 0) {
        out += "memory_limit = " + std::to_string(config.run.memory_limit) + " # " + format_size(config.run.memory_limit) + "\n";
    }
    out += std::string("allow_collapse = ") + (config.run.allow_collapse ? "true" : "false") + "\n";
    out += "on_error = \"" + config.run.on_error + "\"\n";
    return out;
}

std::string check_config(const Config& config)
{
    if (config.run.on_error != "stop" && config.run.on_error != "skip")
        return "on_error must be \"stop\" or \"skip\", got \"" + config.run.on_error + "\"";
    const SnapConfig& s = config.snap;
    auto bad = [](double v) { return !std::isfinite(v); };
    if (s.tolerance && (bad(*s.tolerance) || *s.tolerance <= 0))
        return "tolerance must be finite and > 0, got " + num(*s.tolerance);
    if (s.tolerance && !tolerance_range_error(*s.tolerance).empty())
        return tolerance_range_error(*s.tolerance);
    if (s.tolerance_m && (bad(*s.tolerance_m) || *s.tolerance_m <= 0))
        return "tolerance_m must be finite and > 0, got " + num(*s.tolerance_m);
    if (s.tolerance && s.tolerance_m) return "give tolerance or tolerance_m, not both";
    if (bad(s.edge_separation) || s.edge_separation <= 0 || s.edge_separation > 1)
        return "edge_separation must be in (0, 1], got " + num(s.edge_separation);
    if (bad(s.sliver_factor) || s.sliver_factor < 0)
        return "sliver_factor must be >= 0, got " + num(s.sliver_factor);
    if (bad(s.grid) || s.grid < 0) return "grid must be >= 0, got " + num(s.grid);
    if (bad(s.max_drift_factor) || s.max_drift_factor <= 0)
        return "max_drift_factor must be > 0, got " + num(s.max_drift_factor);
    if (s.max_operations < 0) return "max_operations must be >= 0";
    if (config.run.threads < 0) return "threads must be >= 0";
    const TilingConfig& t = config.tiling;
    if (bad(t.size) || t.size < 0) return "tiling.size must be >= 0 (0 = balanced tiles), got " + num(t.size);
    if (t.vertex_budget < 16) return "tiling.vertex_budget must be >= 16, got " + std::to_string(t.vertex_budget);
    // halo x t x 2^max_growth must stay far inside the double range (frames are built round it).
    if (bad(t.halo) || t.halo < 2 || t.halo > k_max_halo)
        return "tiling.halo must be in [2, 1048576] (a factor of the tolerance), got " + num(t.halo);
    if (t.max_growth < 0 || t.max_growth > 10) return "tiling.max_growth must be in [0, 10], got " + std::to_string(t.max_growth);
    return "";
}

} // namespace trisnap
