#include "app/problem_log.hpp"

#include "tiling/records.hpp"

#include <algorithm>
#include <memory>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <tuple>

namespace trisnap {
namespace {

constexpr std::size_t k_read_buffer = 16 << 10;

void put_logged(tiling::ByteWriter& w, const Problem& p)
{
    w.put<std::uint32_t>(p.layer);
    tiling::put_problem(w, p);
}

Problem get_logged(const std::string& record)
{
    tiling::ByteReader r(record, "problem");
    const auto layer = r.get<std::uint32_t>();
    Problem p = tiling::get_problem(r);
    p.layer = layer;
    return p;
}

// Runs merged in order; ties go to the earlier run, so the result is a stable sort of the runs
// laid end to end. `tail` (sorted, in memory) comes after every run.
class RunMerge {
public:
    RunMerge(const tiling::WorkStore& store, const std::vector<std::string>& runs, std::vector<Problem> tail)
        : m_tail(std::move(tail))
    {
        for (const std::string& name : runs) {
            m_files.push_back(store.open(name));
            m_readers.push_back(std::make_unique<tiling::RecordReader>(*m_files.back(), k_read_buffer));
        }
        m_heads.resize(runs.size() + 1);
        for (std::size_t k = 0; k <= runs.size(); ++k) {
            pull(k);
        }
    }
    bool next(Problem& out)
    {
        if (m_heap.empty()) {
            return false;
        }
        const std::size_t k = m_heap.top();
        m_heap.pop();
        out = std::move(m_heads[k]);
        pull(k);
        return true;
    }

private:
    // On the runs' current heads: the heap's top is the smallest, ties to the earlier run.
    struct Later {
        const std::vector<Problem>* heads;
        bool operator()(std::size_t a, std::size_t b) const
        {
            const Problem& pa = (*heads)[a];
            const Problem& pb = (*heads)[b];
            if (problem_order(pa, pb)) {
                return false;
            }
            if (problem_order(pb, pa)) {
                return true;
            }
            return a > b;
        }
    };
    void pull(std::size_t k)
    {
        if (k < m_readers.size()) {
            std::string record;
            if (m_readers[k]->next(record)) {
                m_heads[k] = get_logged(record);
                m_heap.push(k);
            }
        } else if (m_tail_next < m_tail.size()) {
            m_heads[k] = std::move(m_tail[m_tail_next++]);
            m_heap.push(k);
        }
    }

    std::vector<std::unique_ptr<tiling::InFile>> m_files;
    std::vector<std::unique_ptr<tiling::RecordReader>> m_readers;
    std::vector<Problem> m_tail;
    std::size_t m_tail_next = 0;
    std::vector<Problem> m_heads;
    std::priority_queue<std::size_t, std::vector<std::size_t>, Later> m_heap{Later{&m_heads}}; ///< runs by head
};

} // namespace

bool problem_order(const Problem& a, const Problem& b)
{
    return std::tie(a.layer, a.feature_id, a.code) < std::tie(b.layer, b.feature_id, b.code);
}

ProblemLog::ProblemLog(tiling::WorkStore& store, std::string phase, std::size_t buffer_bytes)
    : m_store(&store), m_phase(std::move(phase)), m_buffer_cap(buffer_bytes)
{
}

void ProblemLog::add(Problem p)
{
    ++m_count;
    ++m_by_code[static_cast<int>(p.code)];
    if (m_by_layer.size() <= p.layer) {
        m_by_layer.resize(p.layer + 1, 0);
    }
    ++m_by_layer[p.layer];
    m_buffer_bytes += sizeof(Problem) + p.message.size();
    m_buffer.push_back(std::move(p));
    if (m_store && m_buffer_bytes > m_buffer_cap) {
        seal();
    }
}

std::uint64_t ProblemLog::in_layer(std::uint32_t layer) const
{
    return layer < m_by_layer.size() ? m_by_layer[layer] : 0;
}

std::string ProblemLog::next_name()
{
    return m_phase + std::to_string(m_next++);
}

void ProblemLog::seal()
{
    if (!m_store || m_buffer.empty()) {
        return;
    }
    std::stable_sort(m_buffer.begin(), m_buffer.end(), problem_order);
    const std::string name = next_name();
    {
        const std::unique_ptr<tiling::OutFile> file = m_store->create(name);
        tiling::RecordWriter writer(*file);
        std::string record;
        for (const Problem& p : m_buffer) {
            record.clear();
            tiling::ByteWriter w(record);
            put_logged(w, p);
            writer.write(record);
        }
        file->commit();
    }
    m_runs.push_back(name);
    std::vector<Problem>().swap(m_buffer);
    m_buffer_bytes = 0;
    if (m_runs.size() - m_phase_first_run >= k_max_runs) {
        merge_phase_runs();
    }
}

// The current phase's runs become one (earlier phases' runs are another process's checkpoint).
void ProblemLog::merge_phase_runs()
{
    const std::vector<std::string> olds(m_runs.begin() + static_cast<std::ptrdiff_t>(m_phase_first_run), m_runs.end());
    const std::string name = next_name();
    {
        RunMerge merge(*m_store, olds, {});
        const std::unique_ptr<tiling::OutFile> file = m_store->create(name);
        tiling::RecordWriter writer(*file);
        std::string record;
        Problem p;
        while (merge.next(p)) {
            record.clear();
            tiling::ByteWriter w(record);
            put_logged(w, p);
            writer.write(record);
        }
        file->commit();
    }
    for (const std::string& old : olds) {
        m_store->remove(old);
    }
    m_runs.resize(m_phase_first_run);
    m_runs.push_back(name);
}

void ProblemLog::begin_phase(const std::string& phase)
{
    seal();
    m_phase = phase;
    m_next = 0;
    m_phase_first_run = m_runs.size();
    if (m_store) {
        m_store->remove_all(phase);
    }
}

void ProblemLog::close()
{
    m_closed = true;
    m_store = nullptr;
    m_runs.clear();
    m_buffer.clear();
}

void ProblemLog::for_each(const std::function<void(const Problem&)>& f) const
{
    if (m_closed) {
        throw std::logic_error("ProblemLog::for_each after close: the work files are gone");
    }
    std::vector<Problem> tail = m_buffer;
    std::stable_sort(tail.begin(), tail.end(), problem_order);
    if (m_runs.empty()) {
        std::for_each(tail.begin(), tail.end(), f);
        return;
    }
    RunMerge merge(*m_store, m_runs, std::move(tail));
    Problem p;
    while (merge.next(p)) {
        f(p);
    }
}

void ProblemLog::save(tiling::ByteWriter& w) const
{
    if (!m_buffer.empty()) {
        throw std::logic_error("ProblemLog::save before seal");
    }
    w.put<std::uint64_t>(m_count);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(m_by_code.size()));
    for (const auto& [code, n] : m_by_code) {
        w.put<std::int32_t>(code);
        w.put<std::uint64_t>(n);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(m_by_layer.size()));
    for (std::uint64_t n : m_by_layer) {
        w.put<std::uint64_t>(n);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(m_runs.size()));
    for (const std::string& name : m_runs) {
        w.put_string(name);
    }
}

void ProblemLog::load(tiling::ByteReader& r)
{
    m_count = r.get<std::uint64_t>();
    m_by_code.clear();
    for (std::uint32_t n = r.get_count(12); n > 0; --n) {
        const auto code = r.get<std::int32_t>();
        m_by_code[code] = r.get<std::uint64_t>();
    }
    m_by_layer.resize(r.get_count(8));
    for (std::uint64_t& n : m_by_layer) {
        n = r.get<std::uint64_t>();
    }
    m_runs.resize(r.get_count(4));
    for (std::string& name : m_runs) {
        name = r.get_string();
    }
    m_buffer.clear();
    m_buffer_bytes = 0;
    m_phase_first_run = m_runs.size();
}

} // namespace trisnap
