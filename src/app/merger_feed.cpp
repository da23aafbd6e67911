#include "app/merger_feed.hpp"

#include <algorithm>
#include <utility>

namespace trisnap {

MergerFeed::MergerFeed(Source source, int threads, std::uint64_t max_bytes)
    : m_source(std::move(source)), m_threads(threads), m_max_bytes(max_bytes)
{
    if (threads > 1) {
        m_thread = std::thread([this] { produce(); });
    }
}

MergerFeed::~MergerFeed() { stop(); }

void MergerFeed::stop()
{
    if (!m_thread.joinable()) {
        m_stopped_inline = true;
        return;
    }
    {
        const std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_changed.notify_all();
    m_thread.join();
    m_done = true;
}

std::uint64_t MergerFeed::bytes_of(const stitch::OutputItem& item)
{
    std::uint64_t n = 0;
    for (const Polygon& p : item.output.geometry.polygons) {
        for (const Path& r : p.rings) {
            n += r.size();
        }
    }
    for (const Path& l : item.output.geometry.lines) {
        n += l.size();
    }
    return n * sizeof(Coord);
}

void MergerFeed::produce()
{
    try {
        for (;;) {
            stitch::OutputItem item;
            const bool more = m_source(item);
            std::unique_lock lock(m_mutex);
            if (!more || m_stop) {
                m_done = true;
                break;
            }
            const std::uint64_t bytes = bytes_of(item);
            m_changed.wait(lock, [&] { return m_stop || m_queue.empty() || m_bytes + bytes <= m_max_bytes; });
            if (m_stop) {
                m_done = true;
                break;
            }
            m_queue.emplace_back(std::move(item), bytes);
            m_bytes += bytes;
            m_peak = std::max(m_peak, m_bytes);
            lock.unlock();
            m_changed.notify_all();
        }
    } catch (...) {
        const std::lock_guard lock(m_mutex);
        m_error = std::current_exception();
        m_done = true;
    }
    m_changed.notify_all();
}

bool MergerFeed::next(stitch::OutputItem& item)
{
    if (m_threads <= 1) {
        return !m_stopped_inline && m_source(item);
    }
    std::unique_lock lock(m_mutex);
    m_changed.wait(lock, [&] { return !m_queue.empty() || m_done; });
    if (m_queue.empty()) {
        if (m_error) {
            std::rethrow_exception(m_error);
        }
        return false;
    }
    item = std::move(m_queue.front().first);
    m_bytes -= m_queue.front().second;
    m_queue.pop_front();
    lock.unlock();
    m_changed.notify_all();
    return true;
}

} // namespace trisnap
