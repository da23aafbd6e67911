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

namespace trisnap::tiling {
namespace {

using Blob = std::shared_ptr<const std::string>;

class MemoryStore;

class MemOutFile : public OutFile {
public:
    MemOutFile(MemoryStore& store, std::string name) : m_store(store), m_name(std::move(name)) {}
    void write(std::string_view bytes) override { m_data.append(bytes); }
    void commit() override;
    std::uint64_t bytes_written() const override { return m_data.size(); }

private:
    MemoryStore& m_store;
    std::string m_name;
    std::string m_data;
};

class MemInFile : public InFile {
public:
    explicit MemInFile(Blob data) : m_data(std::move(data)) {}
    std::size_t read(char* out, std::size_t n) override
    {
        const std::size_t k = std::min(n, m_data->size() - m_pos);
        std::memcpy(out, m_data->data() + m_pos, k);
        m_pos += k;
        return k;
    }
    void read_at(std::uint64_t offset, char* out, std::size_t n) override
    {
        if (offset > m_data->size() || n > m_data->size() - offset) {
            throw work_error("damaged work file in memory: shorter than its records say");
        }
        std::memcpy(out, m_data->data() + offset, n);
    }
    std::uint64_t size() const override { return m_data->size(); }

private:
    Blob m_data;
    std::size_t m_pos = 0;
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
        std::shared_ptr<std::string>& b = m_files[name];
        if (!b) {
            b = std::make_shared<std::string>();
        } else if (b.use_count() > 1) { // someone reads it: leave them their copy
            b = std::make_shared<std::string>(*b);
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

    void install(const std::string& name, std::string data)
    {
        const std::lock_guard lock(m_mutex);
        m_files[name] = std::make_shared<std::string>(std::move(data));
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
    std::map<std::string, std::shared_ptr<std::string>> m_files;
};

void MemOutFile::commit() { m_store.install(m_name, std::move(m_data)); }

} // namespace

std::unique_ptr<WorkStore> make_memory_store() { return std::make_unique<MemoryStore>(); }

} // namespace trisnap::tiling
