#include "app/run_dir.hpp"

#include "app/build_id.hpp"
#include "app/pipeline.hpp"
#include "app/version.hpp"
#include "config/errors.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <set>

#include <signal.h>
#include <unistd.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

const char* const k_record = "cluster.json";

std::string shard_file(std::size_t index, std::size_t count)
{
    return fmt::format("shard-{}-of-{}", index, count);
}

// The path of the first input file whose size or time differs, for the message.
std::string changed_file(const nlohmann::json& planned, const nlohmann::json& now)
{
    const nlohmann::json& a = planned["input"]["files"];
    const nlohmann::json& b = now["input"]["files"];
    for (std::size_t k = 0; k < a.size(); ++k) {
        if (k >= b.size() || a[k] != b[k]) {
            return a[k].value("path", std::string());
        }
    }
    return b.size() > a.size() ? b[a.size()].value("path", std::string()) : std::string();
}

// Every step of a run must be the build that planned it: two builds of one version can snap a
// tile to other bytes (an engine fix), and tiles of two builds would then disagree at the seams.
// A snap's work directory records no build (its --resume checks the version only): not refused here.
void check_build(const nlohmann::json& manifest, const std::string& where)
{
    if (!manifest.contains("cluster")) {
        return;
    }
    const nlohmann::json& build = manifest.value("build", nlohmann::json());
    const std::string planned = build.is_string() ? build.get<std::string>() : std::string("(none recorded)");
    if (planned != build_id()) {
        throw argument_error(fmt::format("{}: planned by trisnap build {}, this is build {}; plan it again with this "
                                         "build, or run every step with the build that planned it", where, planned,
                                         build_id()));
    }
}

std::string text_of(const nlohmann::json& object, const char* key)
{
    return object.at(key).get<std::string>();
}

// The PID in NAME.tmp-HOST-PID when HOST is `host` (the format of tiling/work_store.cpp's
// temp_suffix()); nothing for another host or another file.
std::optional<pid_t> temporary_owner(const std::string& name, const std::string& host)
{
    const std::string mark = ".tmp-" + host + "-";
    const std::size_t at = name.rfind(mark);
    if (at == std::string::npos || at == 0) {
        return std::nullopt;
    }
    const std::string digits = name.substr(at + mark.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) {
        return std::nullopt;
    }
    return static_cast<pid_t>(std::stol(digits));
}

// A process that exists, or that we may not signal, counts as running: only a PID that names no
// process at all (ESRCH) frees its temporary files.
bool process_running(pid_t pid)
{
    return pid <= 0 || ::kill(pid, 0) == 0 || errno != ESRCH;
}

} // namespace

std::string host_name()
{
    char name[256] = {};
    return ::gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

std::string cluster_manifest(const Plan& plan, const SnapArgs& args)
{
    nlohmann::ordered_json m = nlohmann::ordered_json::parse(run_manifest(plan));
    m["build"] = build_id();
    m["cluster"] = {
        {"input", args.input},
        {"layer", args.layers.empty() ? std::string() : args.layers.front()}, // plan refuses several
        {"where", args.where},
        {"bbox", args.bbox.value_or("")},
        {"open_options", args.open_options},
        {"settings", to_toml(plan.config)},
        {"tolerance", fmt::format("{:a}", plan.tolerance)},
        {"tolerance_note", plan.tolerance_note},
    };
    return m.dump(2);
}

void save_plan_record(tiling::WorkStore& store, const PlanRecord& r)
{
    const nlohmann::ordered_json j = {{"tiles", r.tiles}, {"vertices", r.vertices}, {"largest_tile_vertices", r.largest},
                                      {"shards", r.shards}, {"suggested_shards", r.suggested}};
    store.put(k_record, j.dump(2));
}

RunDir RunDir::open(const std::string& path)
{
    RunDir dir(WorkDir::attach(path));
    dir.load_manifest();
    dir.load_record();
    return dir;
}

void RunDir::load_manifest()
{
    const std::string& where = path();
    const nlohmann::json m = nlohmann::json::parse(m_work.manifest(), nullptr, false);
    if (m.is_discarded() || !m.is_object() || m.value("tool", std::string()) != "trisnap") {
        throw argument_error(where + ": manifest.json is not a trisnap manifest; make the run directory again with trisnap plan");
    }
    const std::string version = m.value("version", std::string("unknown"));
    if (version != k_version) {
        throw argument_error(fmt::format("{}: planned by trisnap {}, this is trisnap {}; plan it again with this version, "
                                         "or run every step with trisnap {}", where, version, k_version, version));
    }
    check_build(m, where);
    if (!m.contains("cluster")) {
        throw argument_error(where + ": the work directory of a `trisnap snap` run, not a run directory made by trisnap plan");
    }
    try {
        const nlohmann::json& c = m.at("cluster");
        m_args.input = text_of(c, "input");
        if (std::string layer = text_of(c, "layer"); !layer.empty()) {
            m_args.layers = {layer};
        }
        m_args.where = text_of(c, "where");
        if (std::string bbox = text_of(c, "bbox"); !bbox.empty()) {
            m_args.bbox = bbox;
        }
        m_args.open_options = c.at("open_options").get<std::vector<std::string>>();
        load_config_text(text_of(c, "settings"), where + "/manifest.json (cluster.settings)", m_config);
        m_tolerance = std::strtod(text_of(c, "tolerance").c_str(), nullptr);
    } catch (const nlohmann::json::exception& e) {
        throw argument_error(where + ": damaged manifest.json (" + e.what() + "); make the run directory again with trisnap plan");
    }
    nlohmann::json run = m;
    run.erase("cluster");
    run.erase("build");
    m_run_manifest = run.dump();
}

void RunDir::load_record()
{
    if (!m_work.store().exists(k_record)) {
        throw argument_error(path() + ": the plan did not finish (no " + k_record +
                             "); run the same trisnap plan again with --resume");
    }
    const nlohmann::json r = nlohmann::json::parse(m_work.store().get(k_record), nullptr, false);
    if (r.is_discarded() || !r.is_object()) {
        throw argument_error(path() + ": damaged " + k_record + "; make the run directory again with trisnap plan");
    }
    m_record.tiles = r.value("tiles", std::size_t{0});
    m_record.vertices = r.value("vertices", std::uint64_t{0});
    m_record.largest = r.value("largest_tile_vertices", std::uint64_t{0});
    m_record.shards = r.value("shards", std::size_t{0});
    m_record.suggested = r.value("suggested_shards", std::size_t{0});
}

SnapOptions RunDir::options() const { return engine_options(m_config, m_tolerance); }

stitch::TilingOptions RunDir::tiling() const { return tiling_options(m_config); }

std::vector<std::size_t> RunDir::shard_counts_seen() const
{
    std::set<std::size_t> counts;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(path(), ec)) {
        const std::string name = entry.path().filename().string();
        std::size_t index = 0;
        std::size_t count = 0;
        int end = 0;
        const int got = std::sscanf(name.c_str(), "shard-%zu-of-%zu%n", &index, &count, &end);
        if (got == 2 && static_cast<std::size_t>(end) == name.size() && count > 0) {
            counts.insert(count);
        }
    }
    return {counts.begin(), counts.end()};
}

void RunDir::mark_finished(std::size_t index, std::size_t count, const std::string& summary)
{
    m_work.store().put(shard_file(index, count), summary);
}

std::size_t RunDir::remove_stale_temporaries()
{
    const std::string host = host_name();
    std::vector<fs::path> stale;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(path(), ec)) {
        const std::optional<pid_t> owner = temporary_owner(entry.path().filename().string(), host);
        if (owner && !process_running(*owner)) {
            stale.push_back(entry.path());
        }
    }
    std::size_t removed = 0;
    for (const fs::path& file : stale) {
        removed += fs::remove(file, ec) ? 1 : 0; // another task may have removed it first
    }
    return removed;
}

void RunDir::check_input(const Plan& plan) const
{
    const nlohmann::json planned = nlohmann::json::parse(m_run_manifest);
    const nlohmann::json now = nlohmann::json::parse(run_manifest(plan));
    if (planned == now) {
        return;
    }
    const std::string key = manifest_difference(planned, now);
    if (key.rfind("input.files", 0) == 0) {
        throw argument_error(fmt::format("{}: the input changed since trisnap plan ({} has another size or time); "
                                         "plan again on the input as it is now", path(), changed_file(planned, now)));
    }
    throw argument_error(fmt::format("{}: planned for another input or settings ({} differs); plan again", path(), key));
}

} // namespace trisnap
