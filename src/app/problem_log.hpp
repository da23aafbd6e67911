#pragma once
// The problems of a run, held in memory only up to a bound: a layer whose every feature has a
// problem (a repeated point, a ring closed) has as many problems as features, so under
// --memory-limit they go to the work store as they come. Accepts problems in the order a run
// finds them (read phase, then write phase); gives them back sorted by (layer, FID, code),
// ties in the order found: exactly what a stable sort of them all gives. Counts per code and
// per layer are kept as they come, so summaries need no pass over the problems.
// How: a buffer of at most `buffer_bytes` is stable-sorted and written as a run (a file of
// the store); for_each() merges the runs, ties by run (runs are consecutive stretches of the
// order found). A phase's runs are merged into one when they reach k_max_runs, so the merge
// never holds more than 2 x k_max_runs small read buffers. A log without a store holds
// everything (tests, the in-memory callers that need nothing bounded).
// Failure modes: tiling::work_error when a run cannot be written or read back.
#include "core/problems.hpp"
#include "tiling/binary_io.hpp"
#include "tiling/work_store.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace trisnap {

class ProblemLog {
public:
    /// Runs of one phase are merged into one when there are this many.
    static constexpr std::size_t k_max_runs = 64;

    ProblemLog() = default;
    /// Runs go to `store` as files named `phase` + a number; `buffer_bytes` bounds what is held.
    ProblemLog(tiling::WorkStore& store, std::string phase, std::size_t buffer_bytes);

    void add(Problem p);
    /// Writes what is buffered as a run (a phase's checkpoint: what it found is committed).
    void seal();
    /// Starts another phase: new runs are named `phase` + a number; files of an earlier attempt
    /// at that phase (a run stopped during it) are removed; the runs so far stay.
    void begin_phase(const std::string& phase);

    std::uint64_t size() const { return m_count; }
    bool empty() const { return m_count == 0; }
    /// Problems per code number, in code order.
    const std::map<int, std::uint64_t>& by_code() const { return m_by_code; }
    /// Problems whose FID belongs to input layer `layer`.
    std::uint64_t in_layer(std::uint32_t layer) const;

    /// Calls `f` with every problem, sorted (see above). Throws std::logic_error after close().
    void for_each(const std::function<void(const Problem&)>& f) const;
    /// The store is going away (the work files removed): the counts stay, the problems do not.
    void close();

    /// The runs and counts, for another process continuing the run (read.bin); load() with the
    /// same store and buffer: the runs must still be there.
    void save(tiling::ByteWriter& w) const;
    void load(tiling::ByteReader& r);

    /// Bytes held in memory now (the buffer), and the run files.
    std::size_t buffered_bytes() const { return m_buffer_bytes; }
    const std::vector<std::string>& runs() const { return m_runs; }

private:
    void merge_phase_runs();
    std::string next_name();

    tiling::WorkStore* m_store = nullptr;
    bool m_closed = false;
    std::string m_phase;
    std::size_t m_buffer_cap = 0;
    std::vector<Problem> m_buffer;
    std::size_t m_buffer_bytes = 0;
    std::vector<std::string> m_runs; ///< in the order their problems were found
    std::size_t m_phase_first_run = 0; ///< the current phase's runs are m_runs[this...]
    std::uint64_t m_next = 0;
    std::uint64_t m_count = 0;
    std::map<int, std::uint64_t> m_by_code;
    std::vector<std::uint64_t> m_by_layer;
};

/// The order of a run's problems: input layer, FID, code.
bool problem_order(const Problem& a, const Problem& b);

} // namespace trisnap
