#pragma once
// Temporary files and directories beside a target, named ".NAME.trisnap-tmp-PID" so that the
// next run can tell which ones a dead process left behind (SIGKILL, power loss) and remove them.
#include <filesystem>
#include <string>

namespace trisnap {

/// ".NAME.trisnap-tmp-PID" in the directory of `target`, for this process.
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

/// Removes every ".NAME.trisnap-tmp-PID" beside `target` whose process no longer exists (a live
/// process, ours or another run's, keeps its own). Errors are ignored: this is housekeeping.
void remove_stale_temporaries(const std::filesystem::path& target);

/// fsync of one file or directory (its entries, not what they name); throws io_error naming `what`.
void sync_file(const std::filesystem::path& path, const std::string& what);

/// sync_file() of a file, or of a directory and everything in it.
void sync_tree(const std::filesystem::path& path, const std::string& what);

/// A temporary directory beside a target, created empty (a stale one of a dead run is removed
/// first) and removed with everything in it when it goes out of scope, on success and on any
/// exception alike, unless release() handed it to someone else.
class TempDirectory {
public:
    /// Throws io_error naming `what` when the directory cannot be created.
    TempDirectory(const std::filesystem::path& target, const std::string& what);
    ~TempDirectory();
    TempDirectory(const TempDirectory&) = delete;
    TempDirectory& operator=(const TempDirectory&) = delete;

    const std::filesystem::path& path() const { return m_path; }
    /// The caller takes over removing the directory.
    std::filesystem::path release();

private:
    std::filesystem::path m_path;
    bool m_released = false;
};

} // namespace trisnap
