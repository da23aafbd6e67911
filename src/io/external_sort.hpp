#pragma once
// Sorting more records than memory may hold: sorted runs of at most `capacity` records spilled to
// files in a scratch directory, merged when read (at most k_fan_in runs at once: more are merged
// into longer runs first). With no more than `capacity` records nothing is written and the sort
// happens in memory. The order must be total (ties broken by a unique key): then the sequence read
// is the one std::sort of all records would give, however many runs there were.
//
// Records are trivially copyable and written as their bytes: the files live only as long as the
// sorter, on this machine. Every write, flush and close is checked; a failure calls `fail` with a
// one-line reason (the file and the system's error), which must throw. The files are removed as
// soon as they are merged, and by the destructor.
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

namespace trisnap {

template <class T, class Less>
class ExternalSorter {
    static_assert(std::is_trivially_copyable_v<T>);

public:
    using Fail = std::function<void(const std::string&)>; ///< throws

    /// The most runs merged at once (open files, a read buffer each).
    static constexpr std::size_t k_fan_in = 64;

    /// Files go to `directory` (created when the first run is written), named STEM-N.bin.
    ExternalSorter(std::filesystem::path directory, std::string stem, std::size_t capacity, Less less, Fail fail)
        : m_directory(std::move(directory)), m_stem(std::move(stem)), m_capacity(std::max<std::size_t>(capacity, 1)),
          m_less(std::move(less)), m_fail(std::move(fail))
    {
    }
    ~ExternalSorter()
    {
        m_sources.clear();
        for (const std::filesystem::path& p : m_runs) {
            std::error_code ec;
            std::filesystem::remove(p, ec);
        }
    }
    ExternalSorter(const ExternalSorter&) = delete;
    ExternalSorter& operator=(const ExternalSorter&) = delete;

    /// Records to sort taken whole, before any add(): no copy of what a caller held already (a
    /// buffer beyond the capacity becomes the first run at the next add()).
    void take(std::vector<T>&& records)
    {
        if (m_count != 0) {
            throw std::logic_error("ExternalSorter::take() after records were added");
        }
        m_count = records.size();
        m_buffer = std::move(records);
    }
    void add(const T& record)
    {
        if (m_buffer.size() >= m_capacity) {
            spill();
        }
        m_buffer.push_back(record);
        ++m_count;
    }
    /// What a failure calls from now on (the reader of the runs may say more than their writer).
    void on_failure(Fail fail) { m_fail = std::move(fail); }
    std::uint64_t size() const { return m_count; }
    /// Whether any run went to a file.
    bool spilled() const { return !m_runs.empty(); }

    /// No more add(); next() then gives every record in order.
    void finish()
    {
        if (!m_runs.empty() && !m_buffer.empty()) {
            spill(); // the last run too: its memory is the readers' now
        }
        std::sort(m_buffer.begin(), m_buffer.end(), m_less);
        while (m_runs.size() > k_fan_in) {
            merge_first_runs();
        }
        open_sources(m_runs.size());
    }
    /// The next record in order; false after the last.
    bool next(T& out)
    {
        if (m_runs.empty()) {
            if (m_position == m_buffer.size()) {
                return false;
            }
            out = m_buffer[m_position++];
            return true;
        }
        return pop(out);
    }

private:
    /// One run being read: a file, a block of its records at a time.
    struct Source {
        std::FILE* file = nullptr;
        std::filesystem::path path;
        std::vector<T> block;
        std::size_t at = 0;
        ~Source()
        {
            if (file != nullptr) {
                std::fclose(file);
            }
        }
    };
    static constexpr std::size_t k_block = 4096; ///< records read at once from a run

    std::string reason(const char* what, const std::filesystem::path& p) const
    {
        return std::string(what) + " " + p.string() + ": " + std::strerror(errno);
    }

    std::filesystem::path new_run_path()
    {
        if (m_runs.empty() && m_made == 0) {
            std::error_code ec;
            std::filesystem::create_directories(m_directory, ec);
            if (ec) {
                m_fail("cannot create " + m_directory.string() + ": " + ec.message());
            }
        }
        return m_directory / (m_stem + "-" + std::to_string(m_made++) + ".bin");
    }

    /// Writes `count` records from `next_record` (called that often) to a new run file.
    template <class Next>
    std::filesystem::path write_run(std::size_t count, Next&& next_record)
    {
        const std::filesystem::path path = new_run_path();
        std::FILE* f = std::fopen(path.c_str(), "wb");
        if (f == nullptr) {
            m_fail(reason("cannot create", path));
        }
        std::vector<T> block;
        block.reserve(std::min(count, k_block));
        bool ok = true;
        for (std::size_t i = 0; i < count && ok; ++i) {
            block.push_back(next_record());
            if (block.size() == k_block || i + 1 == count) {
                ok = std::fwrite(block.data(), sizeof(T), block.size(), f) == block.size();
                block.clear();
            }
        }
        ok = std::fflush(f) == 0 && ok;
        const std::string error = ok ? std::string() : reason("cannot write", path);
        if (std::fclose(f) != 0 && ok) {
            m_fail(reason("cannot close", path));
        }
        if (!ok) {
            std::error_code ec;
            std::filesystem::remove(path, ec);
            m_fail(error);
        }
        return path;
    }

    void spill()
    {
        std::sort(m_buffer.begin(), m_buffer.end(), m_less);
        std::size_t i = 0;
        m_runs.push_back(write_run(m_buffer.size(), [&] { return m_buffer[i++]; }));
        m_buffer.clear();
        m_buffer.shrink_to_fit();
    }

    void open_sources(std::size_t count)
    {
        m_sources.clear();
        m_heap.clear();
        for (std::size_t k = 0; k < count; ++k) {
            auto s = std::make_unique<Source>();
            s->path = m_runs[k];
            s->file = std::fopen(s->path.c_str(), "rb");
            if (s->file == nullptr) {
                m_fail(reason("cannot open", s->path));
            }
            m_sources.push_back(std::move(s));
            if (refill(*m_sources.back())) {
                m_heap.push_back(k);
            }
        }
        std::make_heap(m_heap.begin(), m_heap.end(), heap_order());
    }

    bool refill(Source& s)
    {
        s.block.resize(k_block);
        const std::size_t got = std::fread(s.block.data(), sizeof(T), k_block, s.file);
        if (got < k_block && std::ferror(s.file)) {
            m_fail(reason("cannot read", s.path));
        }
        s.block.resize(got);
        s.at = 0;
        return got > 0;
    }

    /// Min-heap of sources by their current record.
    auto heap_order() const
    {
        return [this](std::size_t a, std::size_t b) {
            return m_less(m_sources[b]->block[m_sources[b]->at], m_sources[a]->block[m_sources[a]->at]);
        };
    }

    bool pop(T& out)
    {
        if (m_heap.empty()) {
            return false;
        }
        std::pop_heap(m_heap.begin(), m_heap.end(), heap_order());
        Source& s = *m_sources[m_heap.back()];
        out = s.block[s.at++];
        if (s.at < s.block.size() || refill(s)) {
            std::push_heap(m_heap.begin(), m_heap.end(), heap_order());
        } else {
            m_heap.pop_back();
        }
        return true;
    }

    /// The first k_fan_in runs merged into one new run at the end.
    void merge_first_runs()
    {
        open_sources(k_fan_in);
        std::uint64_t count = 0;
        for (std::size_t k = 0; k < k_fan_in; ++k) {
            std::error_code ec;
            count += std::filesystem::file_size(m_runs[k], ec) / sizeof(T);
        }
        T record{};
        const std::filesystem::path merged = write_run(static_cast<std::size_t>(count), [&] {
            if (!pop(record)) {
                m_fail("a run in " + m_directory.string() + " is shorter than it was written");
            }
            return record;
        });
        m_sources.clear();
        for (std::size_t k = 0; k < k_fan_in; ++k) {
            std::error_code ec;
            std::filesystem::remove(m_runs[k], ec);
        }
        m_runs.erase(m_runs.begin(), m_runs.begin() + static_cast<std::ptrdiff_t>(k_fan_in));
        m_runs.push_back(merged);
    }

    std::filesystem::path m_directory;
    std::string m_stem;
    std::size_t m_capacity;
    Less m_less;
    Fail m_fail;
    std::vector<T> m_buffer;
    std::size_t m_position = 0;
    std::uint64_t m_count = 0;
    std::size_t m_made = 0;
    std::vector<std::filesystem::path> m_runs;
    std::vector<std::unique_ptr<Source>> m_sources;
    std::vector<std::size_t> m_heap;
};

} // namespace trisnap
