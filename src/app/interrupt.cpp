#include "app/interrupt.hpp"

#include <atomic>
#include <stdexcept>

namespace trisnap {
namespace {

std::atomic<int> g_signal{0};

extern "C" void remember_signal(int signal) { g_signal.store(signal); }

} // namespace

InterruptGuard::InterruptGuard()
{
    g_signal.store(0);
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
    if (g_signal.load() != 0) throw std::runtime_error("interrupted while writing; nothing was left at OUT");
}

} // namespace trisnap
