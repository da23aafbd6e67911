#include "io/temp_files.hpp"

#include "io/io_error.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

constexpr const char* k_marker = ".trisnap-tmp-";

fs::path parent_of(const fs::path& target)
{
    return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

/// The PID in ".NAME.trisnap-tmp-PID", or 0 when `entry` is not a temporary of `name`.
pid_t temporary_pid(const std::string& entry, const std::string& name)
{
    const std::string prefix = "." + name + k_marker;
    if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) {
        return 0;
    }
    const std::string digits = entry.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) {
        return 0;
    }
    return static_cast<pid_t>(std::stol(digits));
}

bool process_is_gone(pid_t pid)
{
    return pid != getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

} // namespace

void sync_file(const fs::path& path, const std::string& what)
{
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        throw io_error(what, "", "cannot open " + path.string() + " to flush it: " + std::strerror(errno));
    }
    const int result = ::fsync(fd);
    const int error = errno;
    ::close(fd);
    // Some file systems cannot fsync a directory (EINVAL); the data itself was flushed.
    if (result != 0 && !(error == EINVAL && fs::is_directory(path))) {
        throw io_error(what, "", "cannot flush " + path.string() + " to disk: " + std::strerror(error));
    }
}

fs::path temporary_sibling(const fs::path& target)
{
    std::string name = ".";
    name.append(target.filename().string()).append(k_marker).append(std::to_string(getpid()));
    return parent_of(target) / name;
}

void remove_stale_temporaries(const fs::path& target)
{
    std::error_code ec;
    const std::string name = target.filename().string();
    for (const auto& entry : fs::directory_iterator(parent_of(target), ec)) {
        const pid_t pid = temporary_pid(entry.path().filename().string(), name);
        if (pid > 0 && process_is_gone(pid)) {
            fs::remove_all(entry.path(), ec);
        }
    }
}

void sync_tree(const fs::path& path, const std::string& what)
{
    if (fs::is_directory(path)) {
        for (const auto& entry : fs::directory_iterator(path)) {
            sync_tree(entry.path(), what);
        }
    }
    sync_file(path, what);
}

TempDirectory::TempDirectory(const fs::path& target, const std::string& what)
    : m_path(fs::absolute(temporary_sibling(target)))
{
    remove_stale_temporaries(target);
    std::error_code ec;
    fs::remove_all(m_path, ec); // ours from an earlier writer in this process
    if (!fs::create_directory(m_path, ec)) {
        throw io_error(what, "", "cannot create the temporary directory " + m_path.string() + ": " + ec.message());
    }
}

TempDirectory::~TempDirectory()
{
    if (m_released) {
        return;
    }
    std::error_code ec;
    fs::remove_all(m_path, ec);
}

fs::path TempDirectory::release()
{
    m_released = true;
    return m_path;
}

} // namespace trisnap
