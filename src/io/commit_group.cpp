#include "io/commit_group.hpp"

#include "config/errors.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/temp_files.hpp"

#include <gdal_priv.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

fs::path parent_of(const fs::path& target)
{
    return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

/// rename() that fails with EEXIST instead of replacing an existing `to`.
int rename_without_replacing(const fs::path& from, const fs::path& to)
{
    if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) {
        return 0;
    }
    if (errno != EINVAL && errno != ENOSYS) {
        return -1;
    }
    // The file system has no RENAME_NOREPLACE: link() refuses an existing name just the same.
    if (::link(from.c_str(), to.c_str()) != 0) {
        return -1;
    }
    ::unlink(from.c_str()); // a second name left in the temporary directory goes with it
    return 0;
}

std::string exists_message(const fs::path& target)
{
    return target.string() + ": already exists (it appeared while this run was writing); add --overwrite to replace it";
}

void write_all(int fd, const std::string& text, const std::string& path)
{
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            throw io_error(path, "", std::string("cannot write: ") + std::strerror(n < 0 ? errno : ENOSPC));
        }
        done += static_cast<std::size_t>(n);
    }
}

/// Creates `temp` with the text `write` gives (written in pieces of up to 1 MiB), flushed to
/// disk; throws io_error naming `path`, leaving no `temp`.
void write_flushed_file(const fs::path& temp, const TextWriter& write, const std::string& path)
{
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) {
        throw io_error(path, "", "cannot create " + temp.string() + ": " + std::strerror(errno));
    }
    try {
        constexpr std::size_t k_buffer = 1 << 20;
        std::string buffer;
        write([&](std::string_view piece) {
            buffer.append(piece);
            if (buffer.size() >= k_buffer) {
                write_all(fd, buffer, path);
                buffer.clear();
            }
        });
        write_all(fd, buffer, path);
        if (::fsync(fd) != 0) {
            throw io_error(path, "", std::string("cannot flush to disk: ") + std::strerror(errno));
        }
    } catch (...) {
        ::close(fd);
        ::unlink(temp.c_str());
        throw;
    }
    if (::close(fd) != 0) {
        ::unlink(temp.c_str());
        throw io_error(path, "", std::string("cannot write: ") + std::strerror(errno));
    }
}

} // namespace

CommitGroup::~CommitGroup()
{
    if (m_committed) {
        return;
    }
    std::error_code ec;
    for (const Staged& s : m_staged) {
        fs::remove_all(s.temp, ec);
    }
    clean_up();
}

void CommitGroup::stage(const fs::path& temp, const fs::path& target, bool replace, const std::string& label)
{
    m_staged.push_back(Staged{temp, target, replace, label});
}

void CommitGroup::replace_dataset(const fs::path& target)
{
    m_replace_datasets.push_back(target);
}

void CommitGroup::own_directory(const fs::path& directory)
{
    m_directories.push_back(directory);
}

void CommitGroup::protect(const ProtectedFiles& files)
{
    m_protected.push_back(files);
}

void CommitGroup::check_targets() const
{
    for (const Staged& s : m_staged) {
        for (const ProtectedFiles& p : m_protected) {
            p.refuse(s.target.string(), s.label);
        }
        std::error_code ec;
        if (!s.replace && fs::exists(fs::symlink_status(s.target, ec))) {
            throw argument_error(exists_message(s.target));
        }
    }
}

void CommitGroup::rename_all()
{
    for (std::size_t i = 0; i < m_staged.size(); ++i) {
        const Staged& s = m_staged[i];
        const int result = s.replace ? std::rename(s.temp.c_str(), s.target.c_str())
                                     : rename_without_replacing(s.temp, s.target);
        if (result == 0) {
            continue;
        }
        const int error = errno;
        undo(i);
        if (error == EEXIST) {
            throw argument_error(exists_message(s.target));
        }
        throw io_error(s.target.string(), "", std::string("cannot move the result into place: ") + std::strerror(error));
    }
}

void CommitGroup::undo(std::size_t renamed)
{
    std::error_code ec;
    for (std::size_t i = 0; i < renamed; ++i) {
        fs::remove_all(m_staged[i].target, ec);
    }
}

void CommitGroup::clean_up()
{
    std::error_code ec;
    for (const fs::path& directory : m_directories) {
        fs::remove_all(directory, ec);
    }
    m_directories.clear();
}

void CommitGroup::commit()
{
    check_targets();
    if (m_before_rename) {
        m_before_rename();
    }
    {
        ScopedErrorCapture quiet; // GDAL complains about files that are already gone
        for (const fs::path& target : m_replace_datasets) {
            GDALDriver::QuietDelete(target.string().c_str());
        }
    }
    rename_all();
    m_committed = true;
    for (const Staged& s : m_staged) {
        try {
            sync_file(parent_of(s.target), s.target.string()); // the renames themselves, on disk
        } catch (const io_error&) {
            // The files are complete and in place; a directory that cannot be flushed is no reason to fail.
        }
    }
    clean_up();
}

void check_text_file_target(const std::string& path, const ProtectedFiles& protect, const std::string& label)
{
    protect.refuse(path, label);
    struct stat info{};
    if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
        throw argument_error(label + " " + path + ": is a directory; give a file name");
    }
    if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
        throw argument_error(label + " " + path + ": is not a regular file (a device or a pipe); give a file name");
    }
    const fs::path parent = parent_of(path);
    if (!fs::is_directory(parent)) {
        throw argument_error(label + " " + path + ": the directory " + parent.string() + " does not exist");
    }
    if (::access(parent.c_str(), W_OK) != 0) {
        throw io_error(path, "", "the directory " + parent.string() + " is not writable: " + std::strerror(errno));
    }
}

void stage_text_file(CommitGroup& group, const std::string& path, const std::string& text,
                     const ProtectedFiles& protect, const std::string& label)
{
    stage_text_stream(group, path, [&](const std::function<void(std::string_view)>& put) { put(text); }, protect, label);
}

void stage_text_stream(CommitGroup& group, const std::string& path, const TextWriter& write,
                       const ProtectedFiles& protect, const std::string& label)
{
    check_text_file_target(path, protect, label);
    remove_stale_temporaries(path);
    const fs::path temp = fs::absolute(temporary_sibling(path));
    write_flushed_file(temp, write, path);
    group.stage(temp, path, true, label);
}

void write_text_file_atomically(const std::string& path, const std::string& text, const ProtectedFiles& protect,
                                const std::string& label)
{
    CommitGroup group;
    stage_text_file(group, path, text, protect, label);
    group.commit();
}

} // namespace trisnap
