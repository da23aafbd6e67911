#pragma once
// SIGINT and SIGTERM during a run: the first one is remembered and the run stops at the next
// check (between features while reading and writing, from the engine's progress callback
// inside every running tile while snapping), throws
// `interrupted`, and every scope guard removes what it made: nothing is left at OUT. A second
// signal restores the default action, so a run stuck in one long tile still stops at once
// (its hidden temporary directory is removed by the next run; OUT is never touched).
#include <csignal>
#include <stdexcept>
#include <string>

namespace trisnap {

/// A run stopped by a signal: exit 130 for SIGINT (what shells expect), 1 for SIGTERM.
class interrupted : public std::runtime_error {
public:
    interrupted(int signal, const std::string& message) : std::runtime_error(message), m_signal(signal) {}
    int signal() const { return m_signal; }

private:
    int m_signal;
};

class InterruptGuard {
public:
    InterruptGuard();  ///< catches SIGINT and SIGTERM from now on
    ~InterruptGuard(); ///< restores the previous handlers
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Throws `interrupted` when a signal arrived since construction.
    void check() const;
    /// What the run was doing, for the message ("snapping": "interrupted by SIGINT while snapping").
    void set_activity(const char* activity) { m_activity = activity; }
    /// Replaces the whole message after "interrupted by SIGxxx" (cluster tasks keep their tiles).
    void set_message(const char* message) { m_message = message; }

private:
    const char* m_activity = "reading";
    const char* m_message = nullptr;
    struct sigaction m_old_int{};
    struct sigaction m_old_term{};
};

} // namespace trisnap
