#pragma once
// Progress for people (a bar with elapsed time and ETA, on a TTY only unless forced) and for
// schedulers (JSON lines on stderr). Callers report counts from any one thread at a time; a
// ticker thread redraws the bar twice a second so the elapsed time moves between reports, and
// writes a JSON line at least every 5 seconds while a phase runs. Engine workers never print.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace trisnap {

class Progress {
public:
    /// mode: "auto" (bar when stderr is a TTY), "always", "never".
    Progress(const std::string& mode, bool json_lines);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Starts a phase ("plan", "snap", ...) counting `unit`s ("features", "vertices"); total < 0
    /// when unknown.
    void start(const std::string& phase, std::int64_t total, const std::string& unit = "features");
    /// Reports `done` units (never less than before in a phase).
    void update(std::int64_t done);
    /// The same, with a total that grew or became known only now (> 0; else the total stays):
    /// a phase that found more work, as the stitch's seam merges.
    void update(std::int64_t done, std::int64_t total);
    /// Ends the phase (final bar line, final JSON line): its count becomes its total (a pass it
    /// could skip counts as done), and an unknown total becomes the count.
    void finish();
    /// Ends a phase whose count is not the work done but a result (features written): `done`
    /// is the final count, whatever the total.
    void finish(std::int64_t done);

private:
    using Clock = std::chrono::steady_clock;
    void draw_locked();
    void emit_json_locked(bool final);
    double phase_seconds_locked() const;
    void tick();

    bool m_bar = false;
    bool m_json = false;
    std::mutex m_mutex;
    std::condition_variable m_wake;
    bool m_running = false; ///< a phase is open
    bool m_stop = false;    ///< the ticker ends
    std::string m_phase;
    std::string m_unit;
    std::int64_t m_total = -1;
    std::int64_t m_done = 0;
    Clock::time_point m_phase_start;
    Clock::time_point m_last_draw;
    Clock::time_point m_last_json;
    std::thread m_ticker;
};

} // namespace trisnap
