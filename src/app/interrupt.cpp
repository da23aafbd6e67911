#include "app/interrupt.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <unistd.h>

namespace trisnap {
namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_in_place{false}; ///< the outputs are in place: a signal comes too late to stop the run
bool g_tell = false; ///< stderr is a terminal: say that the first signal was seen

void note(const char* text, std::size_t size)
{
    const ssize_t ignored = write(STDERR_FILENO, text, size);
    static_cast<void>(ignored);
}

extern "C" void remember_signal(int signal)
{
    if (g_signal.exchange(signal) != 0) {
        // The second signal: stop now, the default way.
        std::signal(signal, SIG_DFL);
        std::raise(signal);
        return;
    }
    if (!g_tell) {
        return;
    }
    if (g_in_place.load()) {
        constexpr const char k_note[] = "\ntrisnap: the output is in place already; finishing\n";
        note(k_note, sizeof k_note - 1);
        return;
    }
    constexpr const char k_note[] = "\ntrisnap: stopping at the next feature or tile; signal again to stop at once\n";
    note(k_note, sizeof k_note - 1);
}

const char* signal_name(int signal)
{
    return signal == SIGINT ? "SIGINT" : "SIGTERM";
}

} // namespace

InterruptGuard::InterruptGuard()
{
    g_signal.store(0);
    g_in_place.store(false);
    g_tell = isatty(STDERR_FILENO) != 0;
    struct sigaction action{};
    action.sa_handler = remember_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &m_old_int);
    sigaction(SIGTERM, &action, &m_old_term);
}

InterruptGuard::~InterruptGuard()
{
    sigaction(SIGINT, &m_old_int, nullptr);
    sigaction(SIGTERM, &m_old_term, nullptr);
}

void InterruptGuard::check() const
{
    const int signal = g_signal.load();
    if (signal == 0 || g_in_place.load()) {
        return;
    }
    const std::string name = signal_name(signal);
    if (m_message) {
        throw interrupted(signal, "interrupted by " + name + "; " + m_message);
    }
    throw interrupted(signal, "interrupted by " + name + " while " + m_activity + "; nothing was left at OUT");
}

void InterruptGuard::check_at(const char* point) const
{
    signal_point(point);
    check();
}

void InterruptGuard::outputs_in_place()
{
    g_in_place.store(true);
}

void InterruptGuard::warn_if_too_late() const
{
    const int signal = g_signal.load();
    if (signal != 0 && g_in_place.load()) {
        spdlog::warn("{} came after the output was in place: the run finished", signal_name(signal));
    }
}

void signal_point(const char* point)
{
    const char* spec = std::getenv("TRISNAP_TEST_RAISE");
    if (spec == nullptr) {
        return;
    }
    const std::string_view text(spec);
    const std::size_t colon = text.rfind(':');
    if (colon == std::string_view::npos || text.substr(0, colon) != point) {
        return;
    }
    const std::string_view name = text.substr(colon + 1);
    const int signal = name == "SIGINT" ? SIGINT : name == "SIGTERM" ? SIGTERM : name == "SIGSTOP" ? SIGSTOP : 0;
    if (signal != 0) {
        std::raise(signal);
    }
}

} // namespace trisnap
