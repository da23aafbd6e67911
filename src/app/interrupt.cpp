#include "app/interrupt.hpp"

#include <atomic>
#include <cstring>
#include <unistd.h>

namespace trisnap {
namespace {

std::atomic<int> g_signal{0};
bool g_tell = false; ///< stderr is a terminal: say that the first signal was seen

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
    constexpr const char k_note[] = "\ntrisnap: stopping at the next feature or tile; signal again to stop at once\n";
    const ssize_t ignored = write(STDERR_FILENO, k_note, sizeof k_note - 1);
    static_cast<void>(ignored);
}

} // namespace

InterruptGuard::InterruptGuard()
{
    g_signal.store(0);
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
    if (signal == 0) {
        return;
    }
    const std::string name = signal == SIGINT ? "SIGINT" : "SIGTERM";
    if (m_message) {
        throw interrupted(signal, "interrupted by " + name + "; " + m_message);
    }
    throw interrupted(signal, "interrupted by " + name + " while " + m_activity + "; nothing was left at OUT");
}

} // namespace trisnap
