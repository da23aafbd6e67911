#include "app/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace trisnap {
namespace {

constexpr auto k_redraw = std::chrono::milliseconds(100);
constexpr auto k_tick = std::chrono::milliseconds(500);
constexpr auto k_json_every = std::chrono::seconds(1);
constexpr auto k_json_heartbeat = std::chrono::seconds(5);

std::string clock_text(double seconds)
{
    const auto s = static_cast<long long>(seconds + 0.5);
    if (s >= 3600) {
        return fmt::format("{}h{:02}m", s / 3600, s / 60 % 60);
    }
    if (s >= 60) {
        return fmt::format("{}m{:02}s", s / 60, s % 60);
    }
    return fmt::format("{}s", s);
}

/// Seconds left at the phase's average rate so far; < 0 when nothing is known yet.
double eta_seconds(std::int64_t done, std::int64_t total, double seconds)
{
    if (total <= 0 || done <= 0) {
        return -1;
    }
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
    return seconds * (1 - fraction) / fraction;
}

std::string bar_text(std::int64_t done, std::int64_t total, const std::string& unit, double seconds)
{
    if (total <= 0) {
        return fmt::format("{} {}  {}", done, unit, clock_text(seconds));
    }
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
    const int width = 30;
    const int filled = static_cast<int>(fraction * width);
    const double eta = eta_seconds(done, total, seconds);
    return fmt::format("[{}{}] {:3.0f}%  {}/{} {}  {}  ETA {}", std::string(filled, '#'), std::string(width - filled, '-'),
                       fraction * 100, done, total, unit, clock_text(seconds), eta < 0 ? "?" : clock_text(eta));
}

} // namespace

Progress::Progress(const std::string& mode, bool json_lines)
    : m_bar(mode == "always" || (mode == "auto" && isatty(STDERR_FILENO))), m_json(json_lines)
{
    if (m_bar || m_json) {
        m_ticker = std::thread([this] { tick(); });
    }
}

Progress::~Progress()
{
    {
        const std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    if (m_ticker.joinable()) {
        m_ticker.join();
    }
}

void Progress::start(const std::string& phase, std::int64_t total, const std::string& unit)
{
    const std::lock_guard lock(m_mutex);
    m_phase = phase;
    m_unit = unit;
    m_total = total;
    m_done = 0;
    m_running = true;
    m_phase_start = m_last_draw = m_last_json = Clock::now();
    if (m_json) {
        emit_json_locked(false);
    }
    if (m_bar) {
        draw_locked();
    }
}

void Progress::update(std::int64_t done)
{
    const std::lock_guard lock(m_mutex);
    m_done = std::max(m_done, done);
    const auto now = Clock::now();
    if (m_bar && now - m_last_draw >= k_redraw) {
        draw_locked();
    }
    if (m_json && now - m_last_json >= k_json_every) {
        emit_json_locked(false);
    }
}

void Progress::update(std::int64_t done, std::int64_t total)
{
    if (total > 0) {
        const std::lock_guard lock(m_mutex);
        m_total = total;
    }
    update(done);
}

void Progress::finish()
{
    std::int64_t done = 0;
    {
        const std::lock_guard lock(m_mutex);
        done = m_total >= 0 ? m_total : m_done; // complete: a pass it could skip counts as done
    }
    finish(done);
}

void Progress::finish(std::int64_t done)
{
    const std::lock_guard lock(m_mutex);
    m_running = false;
    m_done = done;
    if (m_total < 0) {
        m_total = done; // known now
    }
    if (m_bar) {
        draw_locked();
        std::fputc('\n', stderr);
    }
    if (m_json) {
        emit_json_locked(true);
    }
}

void Progress::tick()
{
    std::unique_lock lock(m_mutex);
    while (!m_stop) {
        m_wake.wait_for(lock, k_tick);
        if (m_stop || !m_running) {
            continue;
        }
        const auto now = Clock::now();
        if (m_bar && now - m_last_draw >= k_tick) {
            draw_locked();
        }
        if (m_json && now - m_last_json >= k_json_heartbeat) {
            emit_json_locked(false);
        }
    }
}

double Progress::phase_seconds_locked() const
{
    return std::chrono::duration<double>(Clock::now() - m_phase_start).count();
}

void Progress::draw_locked()
{
    m_last_draw = Clock::now();
    const std::string line =
        fmt::format("\r{:<6} {}\x1b[K", m_phase, bar_text(m_done, m_total, m_unit, phase_seconds_locked()));
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
}

void Progress::emit_json_locked(bool final)
{
    m_last_json = Clock::now();
    const double seconds = phase_seconds_locked();
    const double eta = final ? 0.0 : eta_seconds(m_done, m_total, seconds);
    const std::string eta_text = eta < 0 ? "null" : fmt::format("{:.1f}", eta);
    const std::string line = fmt::format(
        "{{\"phase\":\"{}\",\"unit\":\"{}\",\"done\":{},\"total\":{},\"elapsed_s\":{:.3f},\"eta_s\":{},\"finished\":{}}}\n",
        m_phase, m_unit, m_done, m_total, seconds, eta_text, final ? "true" : "false");
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
}

} // namespace trisnap
