#include "config/config.hpp"

#include "config/errors.hpp"
#include "config/size.hpp"
#include "core/snap.hpp"

#include <charconv>
#include <cmath>
#include <functional>
#include <sstream>
#include <type_traits>
#include <vector>

#include <toml++/toml.h>

namespace trisnap {

namespace {

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

/// Reads one TOML value into the config; returns false when the value has the wrong type.
using Setter = std::function<bool(const toml::node&, Config&)>;

struct KeySpec {
    const char* section;
    const char* name;
    Setter set;
};

// One key's setter: a float (integers accepted), an integer or a boolean from the TOML node into
// `field` of `section`; false when the node has another type.
template <typename Section, typename Field>
Setter set(Section Config::*section, Field Section::*field)
{
    return [section, field](const toml::node& n, Config& c) {
        Field& target = (c.*section).*field;
        if constexpr (std::is_same_v<Field, bool>) {
            auto v = n.as_boolean();
            if (v) target = v->get();
            return v != nullptr;
        } else if constexpr (std::is_integral_v<Field>) {
            auto v = n.as_integer();
            if (v) target = static_cast<Field>(v->get());
            return v != nullptr;
        } else {
            auto v = n.value<double>();
            if (v) target = *v;
            return v.has_value();
        }
    };
}

// A size: "2GiB" (see config/size.hpp) or a number of bytes. A bad size throws (the caller
// names file, line and key).
template <typename Section>
Setter set_size(Section Config::*section, std::uint64_t Section::*field)
{
    return [section, field](const toml::node& n, Config& c) {
        std::uint64_t& target = (c.*section).*field;
        if (auto text = n.value<std::string>()) {
            target = parse_size(*text, "size");
            return true;
        }
        if (auto v = n.as_integer(); v && v->get() > 0) {
            target = static_cast<std::uint64_t>(v->get());
            return true;
        }
        return false;
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
        bool ok = false;
        try {
            ok = spec->set(node, config);
        } catch (const argument_error& e) {
            throw config_error(path, line_of(node), full, e.what());
        }
        if (!ok)
            throw config_error(path, line_of(node), full, "wrong type for this key");
    }
}

toml::table parse_toml(const std::string& path)
{
    try {
        return toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        throw config_error(path, static_cast<long>(e.source().begin.line), "",
                           std::string(e.description()));
    }
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
    const toml::table root = parse_toml(path);
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
    return out;
}

std::string check_config(const Config& config)
{
    const SnapConfig& s = config.snap;
    auto bad = [](double v) { return !std::isfinite(v); };
    if (s.tolerance && (bad(*s.tolerance) || *s.tolerance <= 0))
        return "tolerance must be finite and > 0, got " + num(*s.tolerance);
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
    if (bad(t.halo) || t.halo < 2) return "tiling.halo must be >= 2 (a factor of the tolerance), got " + num(t.halo);
    if (t.max_growth < 0 || t.max_growth > 10) return "tiling.max_growth must be in [0, 10], got " + std::to_string(t.max_growth);
    return "";
}

} // namespace trisnap
