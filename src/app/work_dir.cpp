#include "app/work_dir.hpp"

#include "app/command.hpp"

#include "config/errors.hpp"
#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

const char* const k_manifest = "manifest.json";
const char* const k_created = "created-by-trisnap"; ///< the directory goes with the run

std::string first_difference(const nlohmann::json& a, const nlohmann::json& b, const std::string& prefix = "")
{
    if (a.is_object() && b.is_object()) {
        for (const auto& [key, value] : a.items()) {
            if (!b.contains(key)) {
                return prefix + key;
            }
            if (value != b.at(key)) {
                return first_difference(value, b.at(key), prefix + key + ".");
            }
        }
        for (const auto& [key, value] : b.items()) {
            if (!a.contains(key)) {
                return prefix + key;
            }
        }
    }
    return prefix.empty() ? std::string("content") : prefix.substr(0, prefix.size() - 1);
}

bool holds_only_work_files(const fs::path& dir)
{
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().filename() == k_manifest) {
            return true;
        }
    }
    return fs::is_empty(dir);
}

} // namespace

std::string manifest_difference(const nlohmann::json& a, const nlohmann::json& b)
{
    return first_difference(a, b);
}

WorkDir WorkDir::in_memory()
{
    WorkDir w;
    w.m_store = tiling::make_memory_store();
    return w;
}

WorkDir WorkDir::on_disk(const std::string& path, bool resume)
{
    WorkDir w;
    w.m_path = path;
    w.m_resume = resume;
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_directory(path, ec)) {
        throw argument_error("--work-dir " + path + ": is a file, not a directory");
    }
    if (fs::is_directory(path, ec)) {
        if (!holds_only_work_files(path)) {
            throw argument_error("--work-dir " + path + ": holds files that are not a trisnap run; give an empty or new directory");
        }
        if (fs::exists(fs::path(path) / k_manifest) && !resume) {
            throw argument_error("work directory " + path +
                                 " holds an earlier run: add --resume to continue it, or remove the directory");
        }
    } else {
        w.m_created = true;
    }
    try {
        w.m_store = tiling::make_directory_store(path);
        if (w.m_created) {
            w.m_store->put(k_created, "");
        }
    } catch (const tiling::work_error& e) {
        throw io_error(path, "", e.what());
    }
    return w;
}

WorkDir WorkDir::attach(const std::string& path)
{
    std::error_code ec;
    if (!fs::is_directory(path, ec)) {
        throw argument_error(path + ": no such run directory; make one with trisnap plan IN " + path + " --tolerance T");
    }
    if (!fs::exists(fs::path(path) / k_manifest, ec)) {
        throw argument_error(path + ": not a trisnap run directory (no " + k_manifest + "); make one with trisnap plan");
    }
    WorkDir w;
    w.m_path = path;
    w.m_finished = true; // attached: never cleaned up
    try {
        w.m_store = tiling::make_directory_store(path);
    } catch (const tiling::work_error& e) {
        throw io_error(path, "", e.what());
    }
    return w;
}

WorkDir::WorkDir(WorkDir&&) noexcept = default;
WorkDir& WorkDir::operator=(WorkDir&&) noexcept = default;

WorkDir::~WorkDir()
{
    if (m_store && !m_finished) {
        cleanup_after_failure();
    }
}

void WorkDir::bind(const std::string& manifest)
{
    if (!on_disk()) {
        return;
    }
    if (m_resume && m_store->exists(k_manifest)) {
        const nlohmann::json earlier = nlohmann::json::parse(m_store->get(k_manifest), nullptr, false);
        const nlohmann::json now = nlohmann::json::parse(manifest);
        if (earlier.is_discarded() || earlier != now) {
            m_finished = true; // not this run's: leave it exactly as it is
            m_store.reset();
            throw argument_error("work directory " + m_path + " holds a run of another command or input (" +
                                 (earlier.is_discarded() ? std::string("unreadable manifest") : "differs in " + first_difference(earlier, now)) +
                                 "); remove it or give another --work-dir");
        }
        m_resumed = true;
        return;
    }
    m_store->put(k_manifest, manifest);
}

void WorkDir::finish()
{
    m_finished = true;
    if (!on_disk()) {
        m_store.reset();
        return;
    }
    const bool ours = m_created || m_store->exists(k_created);
    m_store.reset();
    std::error_code ec;
    if (ours) {
        fs::remove_all(m_path, ec);
        return;
    }
    for (const auto& entry : fs::directory_iterator(m_path, ec)) {
        fs::remove(entry.path(), ec); // a directory the user gave holds only our files
    }
}

void WorkDir::keep()
{
    m_finished = true;
}

std::string WorkDir::manifest() const
{
    return m_store && m_store->exists(k_manifest) ? m_store->get(k_manifest) : std::string();
}

void WorkDir::cleanup_after_failure() noexcept
{
    if (!on_disk()) {
        return;
    }
    std::error_code ec;
    // Committed work worth continuing: the read pass finished (its metadata is the first
    // thing a resumed run needs).
    if (fs::exists(fs::path(m_path) / "spool.meta", ec)) {
        set_error_note("work directory " + m_path + " kept: add --resume to continue it");
        return;
    }
    m_store.reset();
    if (m_created) {
        fs::remove_all(m_path, ec);
    }
}

std::uint64_t WorkDir::bytes() const { return m_store ? m_store->total_bytes() : 0; }

std::string default_work_dir(const std::string& output)
{
    if (output == "-" || output.rfind("/vsi", 0) == 0) {
        return ".trisnap-work"; // streamed or virtual output: beside nothing, in the current directory
    }
    const fs::path out(output);
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    return (parent / ("." + out.filename().string() + ".trisnap-work")).string();
}

} // namespace trisnap
