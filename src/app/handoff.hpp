#pragma once
// A phase in two stages that run at once on two threads: one that reads and prepares items (the
// write phase: the stitched features, encoded) and one that consumes them in the order read
// (OUT's writer, with the input's attributes read beside it: app/write_phase.cpp says when it
// pays). The consumer sees exactly the sequence a loop would
// give it, so the output does not depend on the thread count; with one thread it is that loop.
// At most `tokens` batches wait: memory stays bounded by the batch size, not by the layer.
//
// Not a tbb::parallel_pipeline (the house default), for the allocator: TBB runs a filter on
// whichever thread takes the token, so what the reading stage allocated (GDAL's features, the
// geometries) was freed on either thread, and glibc's arenas then locked and consolidated on
// nearly every call. Measured on Andorra x43 with two threads: malloc and free took 15-30 % of
// each thread in the write phase, which took 1.6-2.1 s instead of 1.4 s on one thread. Here
// the reading stage has a thread of its own and the consumed batches go back to it to be freed,
// so each thread frees what it allocated.
//
// Each stage touches only its own state (the write phase: the reading stage the work files, the
// consumer stage the input dataset and OUT). An exception in the reading stage reaches the caller after the items read before it
// were consumed (what the loop does); one in the consuming stage stops the reader (once its
// current read returns) and is rethrown. Either way on the calling thread.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace trisnap {

/// How a phase's two stages are cut: a batch closes at `batch` items or once its items weigh
/// `batch_weight` (T::weight(): the features' vertices), and at most `tokens` wait.
/// Each batch can put a waiting thread to sleep and wake it (a futex call each way; on the
/// team's paravirtualised VM tens of microseconds). At 64 items a batch, Andorra x43's write
/// phase (247,551 features, 7.7 vertices each) made ~8,300 futex calls and ~3,000 context
/// switches at two threads; at 512, 1,200 and 520 (the batch weight then closes batches of
/// larger features first). Measured 2026-12-03, 5-7 interleaved runs at two threads, write
/// phase medians: Andorra x43 0.504 -> 0.482 and 0.442 -> 0.423 s (two rounds), Jakarta 0.115
/// -> 0.106 and 0.102 -> 0.098; 4,096 items gave the same as 512.
struct HandoffShape {
    std::size_t batch = 512;
    std::size_t tokens = 4;
    std::size_t batch_weight = std::size_t{1} << 14;
};

namespace detail {

template <class T>
class Handoff {
public:
    explicit Handoff(const HandoffShape& shape) : m_shape(shape) {}

    /// Reading side: hands over a full batch (waits while `tokens` are in flight) and frees the
    /// batches the consumer gave back. False when the consumer stopped.
    bool send(std::vector<T>& batch)
    {
        std::vector<std::vector<T>> spent;
        {
            std::unique_lock lock(m_mutex);
            m_room.wait(lock, [&] { return m_full.size() < m_shape.tokens || m_stopped; });
            if (m_stopped) {
                return false;
            }
            m_full.push_back(std::move(batch));
            spent.swap(m_spent);
        }
        m_ready.notify_one();
        spent.clear(); // here, on the thread that allocated them
        batch = std::vector<T>();
        batch.reserve(m_shape.batch);
        return true;
    }
    /// Reading side, last: no more batches; `error`, if any, is rethrown to the caller.
    void end(std::exception_ptr error)
    {
        {
            const std::lock_guard lock(m_mutex);
            m_ended = true;
            m_error = std::move(error);
        }
        m_ready.notify_one();
    }
    /// Consuming side: the next batch, false when the reading side ended and all were taken.
    bool take(std::vector<T>& batch)
    {
        std::unique_lock lock(m_mutex);
        m_ready.wait(lock, [&] { return !m_full.empty() || m_ended; });
        if (m_full.empty()) {
            return false;
        }
        batch = std::move(m_full.front());
        m_full.pop_front();
        lock.unlock();
        m_room.notify_one();
        return true;
    }
    /// Consuming side: a batch consumed, for the reading side to free.
    void give_back(std::vector<T>&& batch)
    {
        const std::lock_guard lock(m_mutex);
        m_spent.push_back(std::move(batch));
    }
    /// Consuming side, on an error: the reading side stops at its next batch.
    void stop()
    {
        {
            const std::lock_guard lock(m_mutex);
            m_stopped = true;
        }
        m_room.notify_one();
    }
    std::exception_ptr error() const
    {
        const std::lock_guard lock(m_mutex);
        return m_error;
    }

private:
    const HandoffShape m_shape;
    mutable std::mutex m_mutex;
    std::condition_variable m_ready; ///< a batch or the end is there
    std::condition_variable m_room;  ///< fewer than `tokens` in flight, or stopped
    std::deque<std::vector<T>> m_full;
    std::vector<std::vector<T>> m_spent;
    bool m_ended = false;
    bool m_stopped = false;
    std::exception_ptr m_error;
};

} // namespace detail

/// Starts the reading stage's thread (std::thread; a test gives one that fails as a process
/// limit would).
struct StartThread {
    template <class F>
    std::thread operator()(F&& f) const
    {
        return std::thread(std::forward<F>(f));
    }
};

/// Calls `read(item)` until it returns false, and `consume(item)` on every item it filled, in
/// that order. With `two_threads`, reading runs on a thread of its own, ahead of consuming by
/// at most tokens + 2 batches (those waiting, the one consumed, the one filled), each of at
/// most `batch` items and `batch_weight` plus one item's weight; without, or when `start`
/// cannot make the thread (std::system_error), it is a plain loop on this thread.
template <class T, class Read, class Consume, class Start = StartThread>
void hand_off(bool two_threads, const HandoffShape& shape, Read&& read, Consume&& consume, Start&& start = {})
{
    const auto loop = [&] {
        for (;;) {
            T item{};
            if (!read(item)) {
                return;
            }
            consume(item);
        }
    };
    if (!two_threads) {
        loop();
        return;
    }
    detail::Handoff<T> handoff(shape);
    // The reading stage, on its own thread: full batches to the consumer, the consumed ones
    // freed here.
    const auto reading = [&] {
        std::exception_ptr error;
        std::vector<T> batch;
        try {
            batch.reserve(shape.batch);
            std::size_t weight = 0;
            for (bool more = true; more;) {
                T item{};
                more = read(item);
                if (more) {
                    weight += item.weight();
                    batch.push_back(std::move(item));
                }
                if ((!more && !batch.empty()) || batch.size() == shape.batch || weight >= shape.batch_weight) {
                    if (!handoff.send(batch)) {
                        break;
                    }
                    weight = 0;
                }
            }
        } catch (...) {
            error = std::current_exception();
            try {
                if (!batch.empty()) {
                    handoff.send(batch); // what was read before the error is consumed first
                }
            } catch (...) { // out of memory: the first error is the one to report
            }
        }
        handoff.end(error);
    };
    std::thread reader;
    try {
        reader = start(reading);
    } catch (const std::system_error&) { // no thread to be had (a process limit): one it is
        loop();
        return;
    }
    try {
        std::vector<T> batch;
        while (handoff.take(batch)) {
            for (T& item : batch) {
                consume(item);
            }
            handoff.give_back(std::move(batch));
            batch = std::vector<T>();
        }
    } catch (...) {
        handoff.stop();
        reader.join();
        throw;
    }
    reader.join();
    if (std::exception_ptr error = handoff.error()) {
        std::rethrow_exception(error);
    }
}

} // namespace trisnap
