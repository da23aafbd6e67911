#pragma once
// Where a run keeps its work files (tiling/work_store.hpp) and whether it continues an earlier
// run. In memory: nothing on disk. On disk: a directory holding a manifest (what run it belongs
// to: trisnap's version, every file of the input with its size and time, the layer, filters and
// every option that changes the output) and the phases' committed files.
//  - A new run refuses a directory that holds anything (another run, or other files): the
//    user's files are never mixed with, or removed with, the run's.
//  - --resume continues a directory whose manifest matches exactly, and refuses one that does
//    not, naming what differs; with no directory it starts a new run.
//  - After success the files are removed (and the directory, when this run created it); after a
//    failure the directory is kept when it holds committed work (say so: --resume continues
//    it), else removed.
//  - A cluster run (trisnap plan, snap-tiles, stitch) keeps its directory after success
//    (keep()), and its later commands attach() to it: they never remove anything.
#include "tiling/work_store.hpp"

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>

namespace trisnap {

class WorkDir {
public:
    static WorkDir in_memory();
    /// `path` is created when missing. Throws argument_error for a path that is a file, or an
    /// existing directory with other content (without resume), io_error when it cannot be made.
    static WorkDir on_disk(const std::string& path, bool resume);
    /// An existing run's directory, to run more phases of it; nothing in it is ever removed.
    /// Throws argument_error naming `path` when it holds no run (no manifest).
    static WorkDir attach(const std::string& path);

    WorkDir(WorkDir&&) noexcept;
    WorkDir& operator=(WorkDir&&) noexcept;
    ~WorkDir();

    tiling::WorkStore& store() { return *m_store; }
    bool on_disk() const { return !m_path.empty(); }
    const std::string& path() const { return m_path; }
    /// True when an earlier run's manifest matched (the run continues it).
    bool resumed() const { return m_resumed; }

    /// Writes the manifest of a new run, or checks that of the run being resumed. Throws
    /// argument_error naming the first difference.
    void bind(const std::string& manifest);
    /// The run succeeded: remove the work files.
    void finish();
    /// The run succeeded and its files are kept for later commands (trisnap plan).
    void keep();
    /// The manifest as written by bind() (attach(): the earlier run's).
    std::string manifest() const;
    /// Bytes of the work files now.
    std::uint64_t bytes() const;

private:
    WorkDir() = default;
    void cleanup_after_failure() noexcept;

    std::unique_ptr<tiling::WorkStore> m_store;
    std::string m_path;
    bool m_created = false;
    bool m_resume = false;
    bool m_resumed = false;
    bool m_finished = false;
};

/// The first key where two manifests differ ("input.files" for a nested key), for messages.
std::string manifest_difference(const nlohmann::json& a, const nlohmann::json& b);

/// The default work directory for OUT: `.NAME.trisnap-work` beside it.
std::string default_work_dir(const std::string& output);

} // namespace trisnap
