#pragma once
// Where a run keeps what does not fit in memory: its work directory (spooled features, tile
// buckets, tile results), or the same files held in memory when the layer fits (the in-memory
// path). Both behave alike, so one pipeline runs on either.
//
// Guarantees of the directory store: a file created with create() appears under its name only
// when commit() succeeded (written to NAME.tmp-HOST-PID, flushed, fsync'ed, renamed), so a process
// killed at any moment leaves either the whole file or none under that name; every write, flush
// and close is checked and a failure throws work_error naming the file and the system's reason
// (a full disk: disk_full_error). append() is for buckets, which a phase seals as a whole (its checkpoint).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace trisnap::tiling {

/// A work file that cannot be written or read; what() names the file.
class work_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A work file that cannot be written because the disk is full (ENOSPC), a quota is reached
/// (EDQUOT) or a file grew past the largest size allowed (EFBIG, RLIMIT_FSIZE): what() names
/// the file and the system's reason, directory() the work directory.
class disk_full_error : public work_error {
public:
    disk_full_error(const std::string& what, std::string directory) : work_error(what), m_directory(std::move(directory)) {}
    const std::string& directory() const { return m_directory; }

private:
    std::string m_directory;
};

/// A file being written; nothing is visible under its name until commit().
class OutFile {
public:
    virtual ~OutFile() = default;
    virtual void write(std::string_view bytes) = 0;
    /// write(block), for a caller that has no more use for `block`: a file in memory keeps the
    /// block itself as its next bytes instead of copying it.
    virtual void write_block(std::string&& block) { write(block); }
    virtual void commit() = 0;
    virtual std::uint64_t bytes_written() const = 0;
};

/// A committed file: sequential reads, and reads at an offset.
class InFile {
public:
    virtual ~InFile() = default;
    /// Up to n bytes at the current position; 0 at the end.
    virtual std::size_t read(char* out, std::size_t n) = 0;
    /// Exactly n bytes at `offset` (throws work_error when the file is shorter).
    virtual void read_at(std::uint64_t offset, char* out, std::size_t n) = 0;
    virtual std::uint64_t size() const = 0;
};

class WorkStore {
public:
    virtual ~WorkStore() = default;
    virtual std::unique_ptr<OutFile> create(const std::string& name) = 0;
    /// Throws work_error when the file does not exist.
    virtual std::unique_ptr<InFile> open(const std::string& name) const = 0;
    virtual bool exists(const std::string& name) const = 0;
    virtual void remove(const std::string& name) = 0;
    /// Removes every file whose name starts with `prefix`.
    virtual void remove_all(const std::string& prefix) = 0;
    virtual void append(const std::string& name, std::string_view bytes) = 0;
    virtual std::uint64_t size(const std::string& name) const = 0;
    /// Bytes of all files now.
    virtual std::uint64_t total_bytes() const = 0;
    /// Bytes free where the files go (the file system's; unlimited for memory).
    virtual std::uint64_t free_space() const = 0;
    virtual bool on_disk() const = 0;
    /// "work directory DIR" or "memory", for messages.
    virtual std::string where() const = 0;

    void put(const std::string& name, std::string_view bytes);
    std::string get(const std::string& name) const;
};

/// Bytes [begin, end) of another file, as a file of their own: read() runs from `begin`, and
/// read_at() offsets count from it. For readers that each take a part of one file.
class FileRange : public InFile {
public:
    FileRange(std::unique_ptr<InFile> file, std::uint64_t begin, std::uint64_t end);
    std::size_t read(char* out, std::size_t n) override;
    void read_at(std::uint64_t offset, char* out, std::size_t n) override;
    std::uint64_t size() const override { return m_end - m_begin; }

private:
    std::unique_ptr<InFile> m_file;
    std::uint64_t m_begin;
    std::uint64_t m_end;
    std::uint64_t m_pos; ///< in the underlying file
};

/// Files in a directory (created when missing).
std::unique_ptr<WorkStore> make_directory_store(const std::string& directory);
/// Files held in memory.
std::unique_ptr<WorkStore> make_memory_store();

/// Length-prefixed records in an OutFile / InFile.
class RecordWriter {
public:
    explicit RecordWriter(OutFile& file) : m_file(file) {}
    /// Returns the record's offset in the file.
    std::uint64_t write(std::string_view record);

private:
    OutFile& m_file;
};

/// An InFile read through a buffer: small reads without a system call each (a directory
/// store's read() is one; the write phase reads records.bin 16 bytes a feature: on a
/// paravirtualised VM that was 1.2 s of 2.6 in one million features' write phase).
class BufferedReader {
public:
    explicit BufferedReader(InFile& file, std::size_t buffer = std::size_t{64} << 10)
        : m_file(file), m_data(std::make_unique_for_overwrite<char[]>(buffer)), m_room(buffer)
    {
    }
    /// Up to n bytes at the current position: fewer only at the end of the file.
    std::size_t read(char* out, std::size_t n);

private:
    InFile& m_file;
    std::unique_ptr<char[]> m_data;
    std::size_t m_room;
    std::size_t m_size = 0;
    std::size_t m_pos = 0;
};

class RecordReader {
public:
    explicit RecordReader(InFile& file, std::size_t buffer = 1 << 20) : m_file(file), m_capacity(buffer) {}
    /// The next record, or false at the end; throws work_error on a truncated record.
    bool next(std::string& record);
    /// The record at `offset` (as returned by RecordWriter::write).
    std::string at(std::uint64_t offset);

private:
    bool fill(std::size_t n);

    InFile& m_file;
    std::size_t m_capacity;
    /// Bytes read and not yet handed out: m_data[m_pos .. m_size). Allocated for overwrite: a
    /// std::string resized before each read zeroed what the read then wrote (0.7 % of a run's
    /// instructions on Natural Earth's countries).
    std::unique_ptr<char[]> m_data;
    std::size_t m_room = 0;
    std::size_t m_size = 0;
    std::size_t m_pos = 0;
    std::uint64_t m_consumed = 0; ///< bytes read from the file so far
};

} // namespace trisnap::tiling
