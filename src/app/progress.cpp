#include "app/progress.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <unistd.h>

namespace trisnap {
namespace {

using Clock = std::chrono::steady_clock;

std::string bar_text(std::int64_t done, std::int64_t total, double seconds)
{
    if (total <= 0) return fmt::format("{} features  {:.1f}s", done, seconds);
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
    const int width = 30;
    const int filled = static_cast<int>(fraction * width);
    const double eta = fraction > 0 ? seconds * (1 - fraction) / fraction : 0.0;
    return fmt::format("[{}{}] {:3.0f}%  {}/{}  ETA {:.0f}s", std::string(filled, '#'),
                       std::string(width - filled, '-'), fraction * 100, done, total, eta);
}

} // namespace

Progress::Progress(const std::string& mode, bool json_lines)
    : m_bar(mode == "always" || (mode == "auto" && isatty(STDERR_FILENO))), m_json(json_lines)
{
}

void Progress::start(const std::string& phase, std::int64_t total)
{
    m_phase = phase;
    m_total = total;
    m_done = 0;
    m_phase_start = m_last_draw = m_last_json = Clock::now();
    if (m_json) emit_json(false);
    if (m_bar) draw();
}

void Progress::update(std::int64_t done)
{
    m_done = done;
    const auto now = Clock::now();
    if (m_bar && now - m_last_draw >= std::chrono::milliseconds(100)) {
        m_last_draw = now;
        draw();
    }
    if (m_json && now - m_last_json >= std::chrono::seconds(1)) {
        m_last_json = now;
        emit_json(false);
    }
}

void Progress::finish()
{
    if (m_bar) {
        draw();
        std::fputc('\n', stderr);
    }
    if (m_json) emit_json(true);
}

double Progress::phase_seconds() const
{
    return std::chrono::duration<double>(Clock::now() - m_phase_start).count();
}

void Progress::draw()
{
    const std::string line = fmt::format("\r{:<6} {}", m_phase, bar_text(m_done, m_total, phase_seconds()));
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
}

void Progress::emit_json(bool final)
{
    const std::string line =
        fmt::format("{{\"phase\":\"{}\",\"done\":{},\"total\":{},\"elapsed_s\":{:.3f},\"finished\":{}}}\n",
                    m_phase, m_done, m_total, phase_seconds(), final ? "true" : "false");
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
}

} // namespace trisnap
