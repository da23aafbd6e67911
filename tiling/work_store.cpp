#include "tiling/work_store.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

namespace trisnap::tiling {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void fail(const std::string& path, const char* what)
{
    throw work_error(path + ": " + what + ": " + std::strerror(errno));
}

// A write, flush or close that failed: a full disk (or quota, or file size limit) is told apart,
// so that the app can say which directory needs room.
[[noreturn]] void fail_write(const std::string& path, const char* what, const std::string& dir)
{
    const int error = errno;
    if (error == ENOSPC || error == EDQUOT || error == EFBIG) {
        throw disk_full_error(path + ": " + what + ": " + std::strerror(error), dir);
    }
    fail(path, what);
}

void write_all(int fd, const char* data, std::size_t n, const std::string& path, const std::string& dir)
{
    while (n > 0) {
        const ssize_t k = ::write(fd, data, n);
        if (k < 0 && errno == EINTR) {
            continue;
        }
        if (k <= 0) {
            if (k == 0) {
                errno = ENOSPC; // a write that makes no progress: the file system took nothing
            }
            fail_write(path, "cannot write", dir);
        }
        data += k;
        n -= static_cast<std::size_t>(k);
    }
}

// Unique among the processes that may write one name at once, on every machine that shares the
// directory: two array tasks (a requeued one and its predecessor, or Kubernetes pods, where
// every process may be PID 1) never write through the same temporary file.
std::string temp_suffix()
{
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0) {
        host[0] = '\0';
    }
    return ".tmp-" + std::string(host) + "-" + std::to_string(::getpid());
}

class DirOutFile : public OutFile {
public:
    DirOutFile(std::string path, std::string dir) : m_path(std::move(path)), m_temp(m_path + temp_suffix()), m_dir(std::move(dir))
    {
        m_fd = ::open(m_temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (m_fd < 0) {
            fail_write(m_temp, "cannot create", m_dir);
        }
        m_buffer.reserve(k_buffer);
    }
    ~DirOutFile() override
    {
        if (m_fd >= 0) {
            ::close(m_fd);
        }
        if (!m_committed) {
            ::unlink(m_temp.c_str());
        }
    }
    void write(std::string_view bytes) override
    {
        m_written += bytes.size();
        if (m_buffer.size() + bytes.size() > k_buffer) {
            flush();
        }
        if (bytes.size() >= k_buffer) {
            write_all(m_fd, bytes.data(), bytes.size(), m_temp, m_dir);
            return;
        }
        m_buffer.append(bytes);
    }
    void commit() override
    {
        flush();
        if (::fsync(m_fd) != 0) {
            fail_write(m_temp, "cannot flush to disk", m_dir);
        }
        const int fd = m_fd;
        m_fd = -1;
        if (::close(fd) != 0) {
            fail_write(m_temp, "cannot close", m_dir);
        }
        if (::rename(m_temp.c_str(), m_path.c_str()) != 0) {
            fail(m_path, "cannot rename into place");
        }
        m_committed = true;
    }
    std::uint64_t bytes_written() const override { return m_written; }

private:
    static constexpr std::size_t k_buffer = 1 << 20;
    void flush()
    {
        write_all(m_fd, m_buffer.data(), m_buffer.size(), m_temp, m_dir);
        m_buffer.clear();
    }

    std::string m_path;
    std::string m_temp;
    std::string m_dir;
    std::string m_buffer;
    int m_fd = -1;
    bool m_committed = false;
    std::uint64_t m_written = 0;
};

class DirInFile : public InFile {
public:
    explicit DirInFile(std::string path) : m_path(std::move(path))
    {
        m_fd = ::open(m_path.c_str(), O_RDONLY | O_CLOEXEC);
        if (m_fd < 0) {
            fail(m_path, "cannot open");
        }
        struct stat st{};
        if (::fstat(m_fd, &st) != 0) {
            fail(m_path, "cannot stat");
        }
        m_size = static_cast<std::uint64_t>(st.st_size);
    }
    ~DirInFile() override { ::close(m_fd); }
    std::size_t read(char* out, std::size_t n) override
    {
        for (;;) {
            const ssize_t k = ::read(m_fd, out, n);
            if (k < 0 && errno == EINTR) {
                continue;
            }
            if (k < 0) {
                fail(m_path, "cannot read");
            }
            return static_cast<std::size_t>(k);
        }
    }
    void read_at(std::uint64_t offset, char* out, std::size_t n) override
    {
        while (n > 0) {
            const ssize_t k = ::pread(m_fd, out, n, static_cast<off_t>(offset));
            if (k < 0 && errno == EINTR) {
                continue;
            }
            if (k <= 0) {
                throw work_error(m_path + ": damaged work file: shorter than its records say");
            }
            out += k;
            offset += static_cast<std::uint64_t>(k);
            n -= static_cast<std::size_t>(k);
        }
    }
    std::uint64_t size() const override { return m_size; }

private:
    std::string m_path;
    int m_fd = -1;
    std::uint64_t m_size = 0;
};

class DirectoryStore : public WorkStore {
public:
    explicit DirectoryStore(const std::string& dir) : m_dir(dir)
    {
        std::error_code ec;
        fs::create_directories(m_dir, ec);
        if (ec || !fs::is_directory(m_dir)) {
            throw work_error(dir + ": cannot create the work directory: " + ec.message());
        }
    }
    std::unique_ptr<OutFile> create(const std::string& name) override
    {
        return std::make_unique<DirOutFile>(path(name), m_dir);
    }
    std::unique_ptr<InFile> open(const std::string& name) const override { return std::make_unique<DirInFile>(path(name)); }
    bool exists(const std::string& name) const override { return fs::exists(path(name)); }
    void remove(const std::string& name) override
    {
        if (::unlink(path(name).c_str()) != 0 && errno != ENOENT) {
            fail(path(name), "cannot remove");
        }
    }
    void remove_all(const std::string& prefix) override
    {
        for (const auto& entry : fs::directory_iterator(m_dir)) {
            if (entry.path().filename().string().rfind(prefix, 0) == 0) {
                remove(entry.path().filename().string());
            }
        }
    }
    void append(const std::string& name, std::string_view bytes) override
    {
        const std::string p = path(name);
        const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
        if (fd < 0) {
            fail_write(p, "cannot open for appending", m_dir);
        }
        try {
            write_all(fd, bytes.data(), bytes.size(), p, m_dir);
        } catch (...) {
            ::close(fd);
            throw;
        }
        if (::close(fd) != 0) {
            fail_write(p, "cannot close", m_dir);
        }
    }
    std::uint64_t size(const std::string& name) const override
    {
        std::error_code ec;
        const auto n = fs::file_size(path(name), ec);
        return ec ? 0 : n;
    }
    std::uint64_t total_bytes() const override
    {
        std::uint64_t n = 0;
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(m_dir, ec)) {
            n += entry.is_regular_file(ec) ? entry.file_size(ec) : 0;
        }
        return n;
    }
    std::uint64_t free_space() const override
    {
        struct statvfs st{};
        if (::statvfs(m_dir.c_str(), &st) != 0) {
            fail(m_dir, "cannot read the free space");
        }
        return static_cast<std::uint64_t>(st.f_bavail) * st.f_frsize;
    }
    bool on_disk() const override { return true; }
    std::string where() const override { return "work directory " + m_dir; }

private:
    std::string path(const std::string& name) const { return (fs::path(m_dir) / name).string(); }
    std::string m_dir;
};

} // namespace

void WorkStore::put(const std::string& name, std::string_view bytes)
{
    std::unique_ptr<OutFile> f = create(name);
    f->write(bytes);
    f->commit();
}

std::string WorkStore::get(const std::string& name) const
{
    std::unique_ptr<InFile> f = open(name);
    std::string out(f->size(), '\0');
    f->read_at(0, out.data(), out.size());
    return out;
}

std::unique_ptr<WorkStore> make_directory_store(const std::string& directory)
{
    return std::make_unique<DirectoryStore>(directory);
}

std::uint64_t RecordWriter::write(std::string_view record)
{
    const std::uint64_t offset = m_file.bytes_written();
    const auto n = static_cast<std::uint32_t>(record.size());
    m_file.write(std::string_view(reinterpret_cast<const char*>(&n), sizeof n));
    m_file.write(record);
    return offset;
}

FileRange::FileRange(std::unique_ptr<InFile> file, std::uint64_t begin, std::uint64_t end)
    : m_file(std::move(file)), m_begin(begin), m_end(end), m_pos(begin)
{
    if (begin > end || end > m_file->size()) {
        throw work_error("damaged work file: bytes " + std::to_string(begin) + " to " + std::to_string(end) + " of a file of " +
                         std::to_string(m_file->size()));
    }
}

std::size_t FileRange::read(char* out, std::size_t n)
{
    const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(n, m_end - m_pos));
    if (k > 0) {
        m_file->read_at(m_pos, out, k);
        m_pos += k;
    }
    return k;
}

void FileRange::read_at(std::uint64_t offset, char* out, std::size_t n)
{
    if (offset > size() || n > size() - offset) {
        throw work_error("damaged work file: a read past the end of its part");
    }
    m_file->read_at(m_begin + offset, out, n);
}

bool RecordReader::fill(std::size_t n)
{
    if (m_size - m_pos >= n) {
        return true;
    }
    const std::size_t have = m_size - m_pos;
    if (m_pos > 0 && have > 0) {
        std::memmove(m_data.get(), m_data.get() + m_pos, have);
    }
    m_pos = 0;
    m_size = have;
    // A buffer's worth, but no more than the file holds: a reader of a small file (a tile's
    // bucket, a seam file) would otherwise allocate the whole buffer for a few records.
    // The size is a hint only: at least what the record needs is always asked for.
    const std::uint64_t size = m_file.size();
    const std::uint64_t remaining = size > m_consumed ? size - m_consumed : 0;
    const std::size_t want = std::max<std::size_t>(n - have, static_cast<std::size_t>(std::min<std::uint64_t>(m_capacity, remaining)));
    if (have + want > m_room) {
        // At least doubled, as the string grew: a buffer's worth after a leftover fits from then on.
        const std::size_t room = std::max(have + want, 2 * m_room);
        std::unique_ptr<char[]> bigger = std::make_unique_for_overwrite<char[]>(room);
        if (have > 0) {
            std::memcpy(bigger.get(), m_data.get(), have);
        }
        m_data = std::move(bigger);
        m_room = room;
    }
    std::size_t got = 0;
    while (got < want) {
        const std::size_t k = m_file.read(m_data.get() + have + got, want - got);
        if (k == 0) {
            break;
        }
        got += k;
    }
    m_consumed += got;
    m_size = have + got;
    return m_size >= n;
}

std::size_t BufferedReader::read(char* out, std::size_t n)
{
    std::size_t got = 0;
    while (got < n) {
        if (m_pos == m_size) {
            if (n - got >= m_room) { // a large read goes straight to the file
                const std::size_t k = m_file.read(out + got, n - got);
                if (k == 0) {
                    break;
                }
                got += k;
                continue;
            }
            m_size = m_file.read(m_data.get(), m_room);
            m_pos = 0;
            if (m_size == 0) {
                break;
            }
        }
        const std::size_t k = std::min(n - got, m_size - m_pos);
        std::memcpy(out + got, m_data.get() + m_pos, k);
        m_pos += k;
        got += k;
    }
    return got;
}

bool RecordReader::next(std::string& record)
{
    if (!fill(sizeof(std::uint32_t))) {
        if (m_size != m_pos) {
            throw work_error("damaged work file: a record is cut short");
        }
        return false;
    }
    std::uint32_t n = 0;
    std::memcpy(&n, m_data.get() + m_pos, sizeof n);
    const std::size_t buffered = m_size - m_pos - sizeof n;
    if (buffered < n && n > m_capacity) {
        // A record larger than the buffer (a feature across a whole tile: ~1 MB of Natural
        // Earth's land) is read into `record` itself, not through a buffer grown to its size and
        // kept at it: fresh memory costs page faults (REPORT.md, "The stitch's memory").
        record.resize(n);
        std::memcpy(record.data(), m_data.get() + m_pos + sizeof n, buffered);
        std::size_t got = buffered;
        while (got < n) {
            const std::size_t k = m_file.read(record.data() + got, n - got);
            if (k == 0) {
                throw work_error("damaged work file: a record is cut short");
            }
            got += k;
            m_consumed += k;
        }
        m_size = 0;
        m_pos = 0;
        return true;
    }
    if (!fill(sizeof n + n)) {
        throw work_error("damaged work file: a record is cut short");
    }
    record.assign(m_data.get() + m_pos + sizeof n, n);
    m_pos += sizeof n + n;
    return true;
}

std::string RecordReader::at(std::uint64_t offset)
{
    std::uint32_t n = 0;
    m_file.read_at(offset, reinterpret_cast<char*>(&n), sizeof n);
    std::string record(n, '\0');
    m_file.read_at(offset + sizeof n, record.data(), n);
    return record;
}

} // namespace trisnap::tiling
