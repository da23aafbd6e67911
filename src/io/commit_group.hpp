#pragma once
// Deciding several outputs together. Each output (OUT with all its files, the report) is first
// written completely to a temporary place beside its target: closed, every write checked,
// flushed to disk. Only then are they renamed onto their targets, all in one commit(), so a run
// that cannot write its report leaves no OUT either, and a full disk never leaves half a file.
//
// Usage (cmd_snap):
//     CommitGroup group;
//     plan.write.commit_group = &group;    // LayerWriter::commit() stages OUT's files here
//     ... run the pipeline (the writer finishes and stages OUT) ...
//     stage_text_file(group, report_path, report_text, protected_files);
//     group.commit();                      // renames OUT's files, then the report
// Leaving the scope without commit() (any exception) removes everything staged.
#include "io/file_safety.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace trisnap {

/// Files staged for renaming onto their targets. Guarantees: a target that must not be replaced
/// (replace = false) is never replaced, even when another process created it after our first
/// check (renameat2 with RENAME_NOREPLACE, or link() + unlink() where the file system lacks it);
/// a target that is one of the protected files is refused; when a rename fails, the files already
/// renamed by this commit are removed again and nothing staged is left behind. What it cannot
/// undo: a target already replaced (replace = true) by an earlier rename of the same commit.
class CommitGroup {
public:
    CommitGroup() = default;
    ~CommitGroup(); ///< removes every staged file and owned directory unless committed
    CommitGroup(const CommitGroup&) = delete;
    CommitGroup& operator=(const CommitGroup&) = delete;

    /// `temp` (complete, on the same file system) will become `target`. `label` names the
    /// output in messages ("OUT", "--report").
    void stage(const std::filesystem::path& temp, const std::filesystem::path& target, bool replace,
               const std::string& label);
    /// Before renaming, remove the dataset at `target` with GDAL (all of an old Shapefile's files).
    void replace_dataset(const std::filesystem::path& target);
    /// A directory removed, with whatever is left in it, after commit() or on destruction.
    void own_directory(const std::filesystem::path& directory);
    /// Targets that are any of these files are refused (argument_error).
    void protect(const ProtectedFiles& files);
    /// `hook` runs in commit() once the targets are checked, before anything at a target is
    /// touched (an old dataset removed, a file renamed): the last moment a run can still stop
    /// with nothing changed (the CLI checks for signals there). What it throws leaves the group
    /// uncommitted, and its destructor removes everything staged.
    void set_before_rename(std::function<void()> hook) { m_before_rename = std::move(hook); }
    /// Renames everything in the order staged. Throws argument_error for a target that exists
    /// (without replace) or is protected, io_error when a rename fails.
    void commit();
    bool committed() const { return m_committed; }

private:
    struct Staged {
        std::filesystem::path temp;
        std::filesystem::path target;
        bool replace = false;
        std::string label;
    };
    void check_targets() const;
    void rename_all();
    void undo(std::size_t renamed);
    void clean_up();

    std::vector<Staged> m_staged;
    std::vector<std::filesystem::path> m_replace_datasets;
    std::vector<std::filesystem::path> m_directories;
    std::vector<ProtectedFiles> m_protected;
    std::function<void()> m_before_rename;
    bool m_committed = false;
};

/// Writes `text` to ".NAME.trisnap-tmp-PID" beside `path`, checks every write, flushes it to
/// disk and stages it in `group` (replacing an existing regular file at `path`). Throws
/// argument_error when `path` is protected or is not a regular file (a directory, a device
/// such as /dev/full), io_error naming `path` when it cannot be written.
void stage_text_file(CommitGroup& group, const std::string& path, const std::string& text,
                     const ProtectedFiles& protect, const std::string& label);

/// Text written in pieces: calls its argument with each piece, in order.
using TextWriter = std::function<void(const std::function<void(std::string_view)>&)>;

/// stage_text_file() for a text too large to hold (a report with millions of problems): `write`
/// gives it piece by piece; the same checks and guarantees.
void stage_text_stream(CommitGroup& group, const std::string& path, const TextWriter& write,
                       const ProtectedFiles& protect, const std::string& label);

/// stage_text_file() and commit() in one: `path` holds either its old content or all of `text`.
void write_text_file_atomically(const std::string& path, const std::string& text,
                                const ProtectedFiles& protect, const std::string& label);

/// The checks of stage_text_file() that need no writing, for a path given on the command line:
/// not protected, not a directory or device, its directory exists and is writable.
void check_text_file_target(const std::string& path, const ProtectedFiles& protect, const std::string& label);

} // namespace trisnap
