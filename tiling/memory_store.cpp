// The work store in memory: for runs whose estimate fits the memory (the in-memory path goes
// through the same phases and files as the out-of-core one), and for tests.
#include "tiling/work_store.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace trisnap::tiling {
namespace {

/// A file's bytes in chunks that never move: a file grows by a chunk, not by copying what it
/// holds into a buffer twice as large (a std::string's doubling left up to half of it as slack).
/// Measured on Andorra x43 (bench/results/REPORT.md, "Huge pages for the heap"): peak -3 MiB
/// (-6 with the heap in huge pages), time and page faults unchanged. No chunk it allocates is
/// larger than 1 MiB, so every one comes from the heap (app/allocator.hpp). Chunks grow with the
/// file, from 256 bytes (a tile's small files) to 1 MiB. A block handed over whole (adopt(): the
/// read's second thread's records, 4 MiB blocks) becomes a chunk as it is.
///
/// Copies share their chunks: a copy that grows writes into its last chunk past the end of the
/// original, bytes the original never reads (it reads below its own size only).
class Chunks {
public:
    void append(std::string_view bytes)
    {
        while (!bytes.empty()) {
            if (m_chunks.empty() || m_chunks.back().used == m_chunks.back().capacity) {
                add_chunk(bytes.size());
            }
            Chunk& c = m_chunks.back();
            const std::size_t k = std::min(bytes.size(), c.capacity - c.used);
            std::memcpy(c.data.get() + c.used, bytes.data(), k);
            c.used += k;
            m_size += k;
            bytes.remove_prefix(k);
        }
    }
    /// Appends `block`'s bytes by keeping `block` as a chunk of its own: no copy. The chunk is
    /// full (its capacity its size), so the next append() starts a new one.
    void adopt(std::string&& block)
    {
        if (block.empty()) {
            return;
        }
        const auto held = std::make_shared<std::string>(std::move(block));
        const std::size_t n = held->size();
        m_chunks.push_back(Chunk{std::shared_ptr<char[]>(held, held->data()), n, n, m_size});
        m_size += n;
    }
    std::uint64_t size() const { return m_size; }
    /// Bytes [offset, offset + n), which the caller has checked are within size().
    void read(std::uint64_t offset, char* out, std::size_t n) const
    {
        if (n == 0) {
            return;
        }
        // The chunk holding `offset`: the one before the first that starts after it.
        auto k = static_cast<std::size_t>(std::upper_bound(m_chunks.begin(), m_chunks.end(), offset,
                                                           [](std::uint64_t o, const Chunk& c) { return o < c.start; }) -
                                          m_chunks.begin()) - 1;
        for (; n > 0; ++k) {
            const Chunk& c = m_chunks[k];
            const auto at = static_cast<std::size_t>(offset - c.start);
            const std::size_t part = std::min(n, c.used - at);
            std::memcpy(out, c.data.get() + at, part);
            out += part;
            offset += part;
            n -= part;
        }
    }

private:
    struct Chunk {
        std::shared_ptr<char[]> data;
        std::size_t capacity = 0;
        std::size_t used = 0;
        std::uint64_t start = 0; ///< the file offset of its first byte
    };
    void add_chunk(std::size_t wanted)
    {
        constexpr std::uint64_t k_smallest = 256;
        constexpr std::uint64_t k_largest = 1 << 20;
        const auto capacity = static_cast<std::size_t>(
            std::max(std::clamp(m_size, k_smallest, k_largest), std::min<std::uint64_t>(wanted, k_largest)));
        // new char[]: not zeroed (make_shared<char[]> would write every page before we do).
        m_chunks.push_back(Chunk{std::shared_ptr<char[]>(new char[capacity]), capacity, 0, m_size});
    }

    std::vector<Chunk> m_chunks;
    std::uint64_t m_size = 0;
};

using Blob = std::shared_ptr<const Chunks>;

class MemoryStore;

class MemOutFile : public OutFile {
public:
    MemOutFile(MemoryStore& store, std::string name) : m_store(store), m_name(std::move(name)) {}
    void write(std::string_view bytes) override { m_data.append(bytes); }
    void write_block(std::string&& block) override { m_data.adopt(std::move(block)); }
    void commit() override;
    std::uint64_t bytes_written() const override { return m_data.size(); }

private:
    MemoryStore& m_store;
    std::string m_name;
    Chunks m_data;
};

class MemInFile : public InFile {
public:
    explicit MemInFile(Blob data) : m_data(std::move(data)) {}
    std::size_t read(char* out, std::size_t n) override
    {
        const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(n, m_data->size() - m_pos));
        m_data->read(m_pos, out, k);
        m_pos += k;
        return k;
    }
    void read_at(std::uint64_t offset, char* out, std::size_t n) override
    {
        if (offset > m_data->size() || n > m_data->size() - offset) {
            throw work_error("damaged work file in memory: shorter than its records say");
        }
        m_data->read(offset, out, n);
    }
    std::uint64_t size() const override { return m_data->size(); }

private:
    Blob m_data;
    std::uint64_t m_pos = 0;
};

class MemoryStore : public WorkStore {
public:
    std::unique_ptr<OutFile> create(const std::string& name) override { return std::make_unique<MemOutFile>(*this, name); }
    std::unique_ptr<InFile> open(const std::string& name) const override { return std::make_unique<MemInFile>(blob(name)); }
    bool exists(const std::string& name) const override
    {
        const std::lock_guard lock(m_mutex);
        return m_files.count(name) != 0;
    }
    void remove(const std::string& name) override
    {
        const std::lock_guard lock(m_mutex);
        m_files.erase(name);
    }
    void remove_all(const std::string& prefix) override
    {
        const std::lock_guard lock(m_mutex);
        std::erase_if(m_files, [&](const auto& kv) { return kv.first.rfind(prefix, 0) == 0; });
    }
    void append(const std::string& name, std::string_view bytes) override
    {
        const std::lock_guard lock(m_mutex);
        std::shared_ptr<Chunks>& b = m_files[name];
        if (!b) {
            b = std::make_shared<Chunks>();
        } else if (b.use_count() > 1) { // someone reads it: leave them their copy (its chunks shared)
            b = std::make_shared<Chunks>(*b);
        }
        b->append(bytes);
    }
    std::uint64_t size(const std::string& name) const override
    {
        const std::lock_guard lock(m_mutex);
        auto it = m_files.find(name);
        return it == m_files.end() ? 0 : it->second->size();
    }
    std::uint64_t total_bytes() const override
    {
        const std::lock_guard lock(m_mutex);
        std::uint64_t n = 0;
        for (const auto& kv : m_files) {
            n += kv.second->size();
        }
        return n;
    }
    std::uint64_t free_space() const override { return UINT64_MAX; }
    bool on_disk() const override { return false; }
    std::string where() const override { return "memory"; }

    void install(const std::string& name, Chunks data)
    {
        const std::lock_guard lock(m_mutex);
        m_files[name] = std::make_shared<Chunks>(std::move(data));
    }

private:
    Blob blob(const std::string& name) const
    {
        const std::lock_guard lock(m_mutex);
        auto it = m_files.find(name);
        if (it == m_files.end()) {
            throw work_error("work file " + name + " is missing");
        }
        return it->second;
    }

    mutable std::mutex m_mutex;
    std::map<std::string, std::shared_ptr<Chunks>> m_files;
};

void MemOutFile::commit() { m_store.install(m_name, std::move(m_data)); }

} // namespace

std::unique_ptr<WorkStore> make_memory_store() { return std::make_unique<MemoryStore>(); }

} // namespace trisnap::tiling
