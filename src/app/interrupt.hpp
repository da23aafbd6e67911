#pragma once
// SIGINT and SIGTERM during a run: the first one is remembered and the run stops at the next
// check (between features while reading and writing, from the engine's progress callback
// inside every running tile while snapping, at the end of every phase, after OUT's writer has
// closed it and just before the final rename), throws `interrupted`, and every scope guard
// removes what it made: nothing is left at OUT, no report, no temporary. A command holds one
// guard from its start to its end, so no moment of the run gets the default action of the
// first signal. Once the outputs are in place (renamed, an updated GeoPackage's transaction
// committed, or streamed to stdout: `outputs_in_place()`) the run is complete: a signal from
// then on no longer stops it (exit 0), and the command says so in a warning line. A second
// signal restores the default action, so a run stuck in one long tile still stops at once (its
// hidden temporary directory is removed by the next run; OUT is never touched).
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

    /// Throws `interrupted` when a signal arrived since construction, unless the outputs are
    /// already in place.
    void check() const;
    /// signal_point(point), then check(): a named place where a run may stop.
    void check_at(const char* point) const;
    /// What the run was doing, for the message ("snapping": "interrupted by SIGINT while snapping").
    void set_activity(const char* activity) { m_activity = activity; }
    /// Replaces the whole message after "interrupted by SIGxxx" (cluster tasks keep their tiles).
    void set_message(const char* message) { m_message = message; }
    /// The outputs are in place: the run is complete, and a signal no longer stops it.
    void outputs_in_place();
    /// After outputs_in_place(): a warning line on stderr when a signal arrived anyway (it
    /// came too late to stop the run, which finished).
    void warn_if_too_late() const;

private:
    const char* m_activity = "reading";
    const char* m_message = nullptr;
    struct sigaction m_old_int{};
    struct sigaction m_old_term{};
};

/// Test hook, for tests only: with TRISNAP_TEST_RAISE=POINT:SIGNAL in the environment (SIGNAL
/// one of SIGINT, SIGTERM, SIGSTOP), the process raises SIGNAL on itself when it reaches the
/// named point, so a test can put a signal at an exact moment instead of relying on timing.
/// Points: the end of each phase ("plan", "spool", "snap", "stitch"; "write" comes after OUT's
/// writer closed it and staged its files), "report-staged", "before-rename" (the targets were
/// checked, nothing at them touched yet) and "after-rename" (everything in place).
void signal_point(const char* point);

} // namespace trisnap
