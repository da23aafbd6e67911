#pragma once
// Turns the engine's steps into one monotone count of input vertices for SnapProgress (snap.hpp).
// Each step owns a share of the run, measured by the CPU profile of the lean engine on real
// layers (bench/results/REPORT.md, "Lean engine"): points and constraints into the
// triangulation about half, snapping a quarter, labelling a twentieth, extraction the rest.
// Inside a step the caller says how far it is (i of n); the meter calls back when the count has
// grown by a stride (1/256 of the run, at least 4096 vertices) or a step ended, and in the
// snapping step also after k_heartbeat calls without one: its count (the share of the queue
// popped) can stall while a cascade keeps the queue growing, and Ctrl-C, heard in the callback,
// then waited for the end of the cascade (41 s on Andorra at 0.01 degrees). Callers in inner
// loops call it every 256 items or so.
#include "core/snap.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace trisnap::detail {

class WorkMeter {
public:
    enum class Step { points, constraints, snapping, labelling, extraction };

    WorkMeter(const SnapProgress& callback, std::size_t total)
        : m_callback(callback), m_total(total), m_stride(std::max<std::size_t>(total / 256, 4096))
    {
    }

    bool active() const { return static_cast<bool>(m_callback); }

    /// Starts `step` (the steps before it count as done).
    void begin(Step step)
    {
        m_step = static_cast<std::size_t>(step);
        advance(0, 1);
    }

    /// `i` of `n` of the current step done (i <= n; n may grow, `done` stays monotone).
    void advance(std::size_t i, std::size_t n)
    {
        if (!m_callback || n == 0) {
            return;
        }
        double start = 0;
        for (std::size_t s = 0; s < m_step; ++s) {
            start += k_shares[s];
        }
        const double fraction = start + k_shares[m_step] * static_cast<double>(std::min(i, n)) / static_cast<double>(n);
        const auto done = std::min(m_total, static_cast<std::size_t>(fraction * static_cast<double>(m_total)));
        const bool heartbeat = m_step == static_cast<std::size_t>(Step::snapping) && ++m_quiet >= k_heartbeat;
        if (done >= m_reported + m_stride || (i >= n && done > m_reported) || heartbeat) {
            m_reported = std::max(m_reported, done);
            m_quiet = 0;
            m_callback(m_reported, m_total);
        }
    }

    /// The run is over: done == total (called once, even for an empty run).
    void finish()
    {
        if (m_callback) {
            m_reported = m_total;
            m_callback(m_total, m_total);
        }
    }

private:
    static constexpr std::array<double, 5> k_shares{0.15, 0.35, 0.25, 0.05, 0.20};
    static constexpr std::size_t k_heartbeat = 64;
    const SnapProgress& m_callback;
    std::size_t m_total;
    std::size_t m_stride;
    std::size_t m_step = 0;
    std::size_t m_reported = 0;
    std::size_t m_quiet = 0; ///< calls since the last callback
};

} // namespace trisnap::detail
