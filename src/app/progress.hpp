#pragma once
// Progress for people (a bar with ETA, on a TTY only unless forced) and for schedulers (JSON
// lines on stderr). Only the main thread calls this; engine workers never print.
#include <chrono>
#include <cstdint>
#include <string>

namespace trisnap {

class Progress {
public:
    /// mode: "auto" (bar when stderr is a TTY), "always", "never".
    Progress(const std::string& mode, bool json_lines);
    /// Starts a phase ("read", "snap", "write"); total < 0 when unknown.
    void start(const std::string& phase, std::int64_t total);
    /// Reports `done` units; redraws at most ~10 times a second.
    void update(std::int64_t done);
    /// Ends the phase (final bar line, final JSON line).
    void finish();

private:
    void draw();
    void emit_json(bool final);
    double phase_seconds() const;

    bool m_bar = false;
    bool m_json = false;
    std::string m_phase;
    std::int64_t m_total = -1;
    std::int64_t m_done = 0;
    std::chrono::steady_clock::time_point m_phase_start;
    std::chrono::steady_clock::time_point m_last_draw;
    std::chrono::steady_clock::time_point m_last_json;
};

} // namespace trisnap
