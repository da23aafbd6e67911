#pragma once
// The stitched features for the write phase, assembled one step ahead on a thread of their own
// while the main thread reads attributes and writes (GDAL): the write phase's two halves overlap
// instead of taking turns. Features come out in the source's order, exactly as without it.
//
// With `threads` <= 1 there is no thread: next() calls the source (a one-thread run stays on one
// core). Otherwise a producer calls the source until it ends, keeping at most `max_bytes` of
// coordinates queued (always at least one feature, however large). An exception the source throws
// is thrown again by the next() that reaches its place; stop() or destroying the feed stops the
// producer after the call in progress and joins it (a consumer that throws never leaves it
// running, and nothing calls the source once stop() returned).
#include "stitch/output.hpp"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace trisnap {

class MergerFeed {
public:
    using Source = std::function<bool(stitch::OutputItem&)>;
    MergerFeed(Source source, int threads, std::uint64_t max_bytes);
    ~MergerFeed();
    MergerFeed(const MergerFeed&) = delete;
    MergerFeed& operator=(const MergerFeed&) = delete;

    /// The next feature; false at the source's end (the producer has then finished).
    bool next(stitch::OutputItem& item);
    /// Stops the producer after the call in progress and joins it (also done on destruction);
    /// after it, the source is not called again and next() gives what was queued, then false.
    void stop();
    /// The most coordinate bytes that were queued at once (tests, and the bound's proof).
    std::uint64_t peak_bytes() const { return m_peak; }

    /// Bytes of coordinates a feature holds (what the queue's bound counts).
    static std::uint64_t bytes_of(const stitch::OutputItem& item);

private:
    void produce();

    Source m_source;
    int m_threads;
    std::uint64_t m_max_bytes;
    bool m_stopped_inline = false; ///< stop() without a thread
    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::deque<std::pair<stitch::OutputItem, std::uint64_t>> m_queue; ///< item, its bytes
    std::uint64_t m_bytes = 0;
    std::uint64_t m_peak = 0;
    bool m_done = false;  ///< the source ended or threw
    bool m_stop = false;  ///< the consumer left
    std::exception_ptr m_error;
    std::thread m_thread;
};

} // namespace trisnap
