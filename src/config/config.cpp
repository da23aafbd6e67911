#include "config/config.hpp"

#include "config/errors.hpp"
#include "core/snap.hpp"

#include <cmath>
#include <functional>
#include <sstream>
#include <vector>

#include <toml++/toml.h>

namespace trisnap {

config_error::config_error(const std::string& file, long line, const std::string& key,
                           const std::string& reason)
    : std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                         (key.empty() ? reason : "key '" + key + "': " + reason)),
      m_file(file), m_line(line), m_key(key)
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

Setter set_double(double SnapConfig::*field)
{
    return [field](const toml::node& n, Config& c) {
        auto v = n.value<double>();
        if (v) c.snap.*field = *v;
        return v.has_value();
    };
}

Setter set_optional(std::optional<double> SnapConfig::*field)
{
    return [field](const toml::node& n, Config& c) {
        auto v = n.value<double>();
        if (v) c.snap.*field = *v;
        return v.has_value();
    };
}

const std::vector<KeySpec>& key_specs()
{
    static const std::vector<KeySpec> specs{
        {"snap", "tolerance", set_optional(&SnapConfig::tolerance)},
        {"snap", "tolerance_m", set_optional(&SnapConfig::tolerance_m)},
        {"snap", "edge_separation", set_double(&SnapConfig::edge_separation)},
        {"snap", "sliver_factor", set_double(&SnapConfig::sliver_factor)},
        {"snap", "grid", set_double(&SnapConfig::grid)},
        {"snap", "max_drift_factor", set_double(&SnapConfig::max_drift_factor)},
        {"snap", "max_operations", [](const toml::node& n, Config& c) {
             auto v = n.as_integer();
             if (v) c.snap.max_operations = v->get();
             return v != nullptr;
         }},
        {"run", "threads", [](const toml::node& n, Config& c) {
             auto v = n.as_integer();
             if (v) c.run.threads = static_cast<int>(v->get());
             return v != nullptr;
         }},
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

long line_of(const toml::node& node) { return static_cast<long>(node.source().begin.line); }

void load_section(const std::string& path, const std::string& section, const toml::table& table,
                  Config& config)
{
    for (auto&& [key, node] : table) {
        const std::string full = section + "." + std::string(key.str());
        const KeySpec* spec = find_spec(section, key.str());
        if (!spec) throw config_error(path, line_of(node), full, "unknown key");
        if (!spec->set(node, config))
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
        const bool known = section == "snap" || section == "run";
        if (!known || !node.is_table())
            throw config_error(path, line_of(node), section,
                               known ? "must be a table" : "unknown section (expected [snap] or [run])");
        load_section(path, section, *node.as_table(), config);
    }
}

std::string to_toml(const Config& config)
{
    toml::table snap;
    if (config.snap.tolerance) snap.insert("tolerance", *config.snap.tolerance);
    if (config.snap.tolerance_m) snap.insert("tolerance_m", *config.snap.tolerance_m);
    snap.insert("edge_separation", config.snap.edge_separation);
    snap.insert("sliver_factor", config.snap.sliver_factor);
    snap.insert("grid", config.snap.grid);
    snap.insert("max_drift_factor", config.snap.max_drift_factor);
    snap.insert("max_operations", config.snap.max_operations);
    toml::table run;
    run.insert("threads", config.run.threads);
    toml::table root;
    root.insert("snap", std::move(snap));
    root.insert("run", std::move(run));
    std::ostringstream out;
    out << root << "\n";
    return out.str();
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
    return "";
}

} // namespace trisnap
