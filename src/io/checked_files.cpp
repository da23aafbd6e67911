#include "io/checked_files.hpp"

#include <cpl_vsi.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>

namespace trisnap {
namespace {

// Installed without a trailing '/', so the callbacks get the absolute local path, '/' included.
constexpr const char* k_prefix = "/vsitrisnap_checked";

/// Written bytes after which the kernel is asked to start writing them to disk.
constexpr std::uint64_t k_writeback_bytes = 8u << 20;

/// One open file: the local GDAL handle everything is forwarded to, and its path for messages.
struct CheckedFile {
    VSILFILE* file = nullptr;
    std::string path;
    int fd = -1;                ///< the same file, for sync_file_range (-1: none)
    std::uint64_t unsynced = 0; ///< bytes written since writeback was last started
};

std::mutex g_mutex;
std::map<std::string, std::string> g_failures; ///< path -> first failure, guarded by g_mutex
std::atomic<std::size_t> g_failure_count{0};    ///< entries in g_failures: the check per feature is free

void record_failure(const std::string& path, const char* what)
{
    const std::string reason = errno != 0 ? std::strerror(errno) : "the operation failed";
    const std::lock_guard lock(g_mutex);
    if (g_failures.emplace(path, std::string(what) + " failed: " + reason).second) {
        ++g_failure_count;
    }
}

CheckedFile* as_file(void* handle)
{
    return static_cast<CheckedFile*>(handle);
}

void* open_file(void*, const char* filename, const char* access)
{
    VSILFILE* file = VSIFOpenL(filename, access);
    if (file == nullptr) {
        return nullptr;
    }
    auto* f = new CheckedFile{file, filename};
    const std::string mode = access;
    if (mode.find_first_of("wa+") != std::string::npos) {
        f->fd = ::open(filename, O_RDONLY | O_CLOEXEC);
    }
    return f;
}

// A file written for OUT is synced to disk before it goes into place (io/temp_files.hpp): that
// fsync waited for all of it (65-106 ms for Andorra x43's 63 MB GeoPackage). Writeback started as
// the bytes come lets the disk write while the run works. Only a hint: an error shows at the
// fsync, which checks everything.
void start_writeback(CheckedFile& f, std::uint64_t bytes)
{
#ifdef __linux__
    f.unsynced += bytes;
    if (f.fd >= 0 && f.unsynced >= k_writeback_bytes) {
        ::sync_file_range(f.fd, 0, 0, SYNC_FILE_RANGE_WRITE);
        f.unsynced = 0;
    }
#else
    (void)f;
    (void)bytes;
#endif
}

vsi_l_offset tell_file(void* handle)
{
    return VSIFTellL(as_file(handle)->file);
}

int seek_file(void* handle, vsi_l_offset offset, int whence)
{
    return VSIFSeekL(as_file(handle)->file, offset, whence);
}

size_t read_file(void* handle, void* buffer, size_t size, size_t count)
{
    return VSIFReadL(buffer, size, count, as_file(handle)->file);
}

int eof_file(void* handle)
{
    return VSIFEofL(as_file(handle)->file);
}

size_t write_file(void* handle, const void* buffer, size_t size, size_t count)
{
    CheckedFile* f = as_file(handle);
    errno = 0;
    const size_t written = VSIFWriteL(buffer, size, count, f->file);
    if (written != count) {
        record_failure(f->path, "write");
    }
    start_writeback(*f, static_cast<std::uint64_t>(written) * size);
    return written;
}

/// `result` of a flush, truncate or close (0 = success), recorded when it failed.
int checked(const CheckedFile& f, const char* what, int result)
{
    if (result != 0) {
        record_failure(f.path, what);
    }
    return result;
}

int flush_file(void* handle)
{
    errno = 0;
    return checked(*as_file(handle), "flush", VSIFFlushL(as_file(handle)->file));
}

int truncate_file(void* handle, vsi_l_offset size)
{
    errno = 0;
    return checked(*as_file(handle), "truncate", VSIFTruncateL(as_file(handle)->file, size));
}

int close_file(void* handle)
{
    const std::unique_ptr<CheckedFile> f(as_file(handle));
    if (f->fd >= 0) {
        ::close(f->fd);
    }
    errno = 0;
    return checked(*f, "close", VSIFCloseL(f->file));
}

int stat_path(void*, const char* filename, VSIStatBufL* buffer, int flags)
{
    return VSIStatExL(filename, buffer, flags);
}

int unlink_path(void*, const char* filename)
{
    return VSIUnlink(filename);
}

int rename_path(void*, const char* from, const char* to)
{
    return VSIRename(from, to);
}

int mkdir_path(void*, const char* dirname, long mode)
{
    return VSIMkdir(dirname, mode);
}

int rmdir_path(void*, const char* dirname)
{
    return VSIRmdir(dirname);
}

char** read_directory(void*, const char* dirname, int max_files)
{
    return VSIReadDirEx(dirname, max_files);
}

/// Every call forwarded to the local file system; the file calls that write are checked.
void set_callbacks(VSIFilesystemPluginCallbacksStruct& cb)
{
    cb.open = open_file;
    cb.tell = tell_file;
    cb.seek = seek_file;
    cb.read = read_file;
    cb.eof = eof_file;
    cb.write = write_file;
    cb.flush = flush_file;
    cb.truncate = truncate_file;
    cb.close = close_file;
    cb.stat = stat_path;
    cb.unlink = unlink_path;
    cb.rename = rename_path;
    cb.mkdir = mkdir_path;
    cb.rmdir = rmdir_path;
    cb.read_dir = read_directory;
}

void install()
{
    VSIFilesystemPluginCallbacksStruct* cb = VSIAllocFilesystemPluginCallbacksStruct();
    set_callbacks(*cb);
    VSIInstallPluginHandler(k_prefix, cb);
    VSIFreeFilesystemPluginCallbacksStruct(cb); // the handler keeps its own copy
}

bool is_under(const std::string& path, const std::string& directory)
{
    return path.compare(0, directory.size(), directory) == 0 &&
           (path.size() == directory.size() || path[directory.size()] == '/');
}

} // namespace

std::string checked_path(const std::filesystem::path& path)
{
    static std::once_flag installed;
    std::call_once(installed, install);
    return k_prefix + std::filesystem::absolute(path).lexically_normal().string();
}

std::string take_write_failure(const std::filesystem::path& directory)
{
    if (g_failure_count.load() == 0) {
        return "";
    }
    const std::string dir = std::filesystem::absolute(directory).lexically_normal().string();
    const std::lock_guard lock(g_mutex);
    std::string first;
    for (auto it = g_failures.begin(); it != g_failures.end();) {
        if (!is_under(it->first, dir)) {
            ++it;
            continue;
        }
        if (first.empty()) {
            first = std::filesystem::path(it->first).lexically_relative(dir).string() + ": " + it->second;
        }
        it = g_failures.erase(it);
        --g_failure_count;
    }
    return first;
}

} // namespace trisnap
