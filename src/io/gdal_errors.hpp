#pragma once
// Scoped capture of GDAL/OGR error messages. GDAL reports errors through a per-thread handler
// stack; while a ScopedErrorCapture lives, messages are collected here instead of printed, and
// our own code decides whether to throw (never from inside the handler, which is a C callback).
#include <string>
#include <vector>

namespace trisnap {

class ScopedErrorCapture {
public:
    ScopedErrorCapture();
    ~ScopedErrorCapture();
    ScopedErrorCapture(const ScopedErrorCapture&) = delete;
    ScopedErrorCapture& operator=(const ScopedErrorCapture&) = delete;

    const std::vector<std::string>& errors() const { return m_errors; }
    const std::vector<std::string>& warnings() const { return m_warnings; }
    /// The last error, or `fallback` when GDAL said nothing.
    std::string last_error(const std::string& fallback = "unknown GDAL error") const;
    void clear();

    /// Called by the GDAL handler; public only so the C callback can reach it.
    void record(int severity, const char* message);

private:
    std::vector<std::string> m_errors;
    std::vector<std::string> m_warnings;
};

} // namespace trisnap
