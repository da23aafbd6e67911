// What the tiled run's scheduler shares between the tiles in flight: the progress count and
// the memory pool. Used by stitch/tiled_snap.cpp only.
#pragma once

#include "stitch/tiled_snap.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace trisnap::stitch {

// The vertices done, for the bar, while tiles run: a finished tile counts whole, a running one by
// the engine's own progress scaled to its vertex estimate. Calls to `progress` are serialised
// and never go backwards; a worker that finds the lock taken skips its update.
class LiveCount {
public:
    LiveCount(const TileProgress& progress, std::uint64_t total) : m_progress(progress), m_total(total) {}

    /// A running tile of `vertices` is at done/of; `share` is what it added so far.
    void running(std::uint64_t& share, std::uint64_t vertices, std::size_t done, std::size_t of)
    {
        const std::uint64_t now = of == 0 ? 0 : static_cast<std::uint64_t>(static_cast<double>(vertices) * static_cast<double>(done) / static_cast<double>(of));
        if (!m_progress || now <= share) {
            return;
        }
        m_running.fetch_add(now - share);
        share = now;
        const std::unique_lock lock(m_mutex, std::try_to_lock);
        if (lock.owns_lock()) {
            emit();
        }
    }

    /// A tile of `vertices` finished; its running share is replaced by all of it.
    void finished(std::uint64_t share, std::uint64_t vertices)
    {
        const std::lock_guard lock(m_mutex);
        m_running.fetch_sub(share);
        m_done += vertices;
        if (m_progress) {
            emit();
        }
    }

private:
    void emit()
    {
        m_last = std::max(m_last, std::min(m_total, m_done + m_running.load()));
        m_progress(m_last, m_total);
    }

    const TileProgress& m_progress;
    std::uint64_t m_total;
    std::mutex m_mutex;
    std::uint64_t m_done = 0;
    std::atomic<std::uint64_t> m_running{0};
    std::uint64_t m_last = 0;
};

// Bytes reserved by the tiles in flight; a tile waits until its estimate fits in the pool (a
// pool of 0: no limit). A tile larger than the pool runs when nothing else does.
class MemoryGate {
public:
    explicit MemoryGate(std::uint64_t pool) : m_pool(pool) {}
    void acquire(std::uint64_t bytes)
    {
        if (m_pool == 0) {
            return;
        }
        std::unique_lock lock(m_mutex);
        m_free.wait(lock, [&] { return m_used == 0 || m_used + bytes <= m_pool; });
        m_used += bytes;
    }
    void release(std::uint64_t bytes)
    {
        if (m_pool == 0) {
            return;
        }
        {
            const std::lock_guard lock(m_mutex);
            m_used -= bytes;
        }
        m_free.notify_all();
    }

private:
    std::uint64_t m_pool;
    std::uint64_t m_used = 0;
    std::mutex m_mutex;
    std::condition_variable m_free;
};

} // namespace trisnap::stitch
