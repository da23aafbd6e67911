#pragma once
// Ctrl-C while the output is being written: stop at the next feature and throw, so the writer's
// destructor removes its temporary directory. Installed only around the write phase; elsewhere
// (reading, snapping) nothing exists at OUT yet and the default action (terminate) is right.
#include <csignal>

namespace trisnap {

class InterruptGuard {
public:
    InterruptGuard();  ///< catches SIGINT and SIGTERM from now on
    ~InterruptGuard(); ///< restores the previous handlers
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Throws std::runtime_error when a signal arrived since construction.
    void check() const;

private:
    struct sigaction m_old_int{};
    struct sigaction m_old_term{};
};

} // namespace trisnap
