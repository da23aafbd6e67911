// Process-wide settings shared by the commands: logging and thread limits.
#include "app/command.hpp"

#include "app/allocator.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>

#include <string>

namespace trisnap {
namespace {

/// GDAL messages that no ScopedErrorCapture caught, and all of GDAL's CPLDebug lines (captures
/// pass those on): debug logs, never raw stderr lines.
void CPL_STDCALL log_gdal_message(CPLErr severity, CPLErrorNum, const char* message)
{
    const char* kind = severity == CE_Debug ? "debug" : severity == CE_Warning ? "warning" : "error";
    spdlog::debug("GDAL {}: {}", kind, message ? message : "");
}

} // namespace

namespace {
std::string g_error_note;
} // namespace

void set_error_note(const std::string& note) { g_error_note = note; }

const std::string& error_note() { return g_error_note; }

void setup_logging(int verbose, int quiet)
{
    // GDAL's workers may log too: the thread-safe sink.
    auto logger = spdlog::stderr_logger_mt("trisnap");
    logger->set_pattern("trisnap: %l: %v");
    spdlog::level::level_enum level = spdlog::level::warn;
    if (quiet > 0) level = spdlog::level::err;
    else if (verbose == 1) level = spdlog::level::info;
    else if (verbose >= 2) level = spdlog::level::debug;
    logger->set_level(level);
    spdlog::set_default_logger(logger);
    CPLSetErrorHandler(log_gdal_message);
    if (verbose >= 2 && quiet == 0 && !CPLGetConfigOption("CPL_DEBUG", nullptr)) {
        CPLSetConfigOption("CPL_DEBUG", "ON"); // -vv: GDAL's own debug lines
    }
    if (const std::string& setting = huge_page_choice().ignored_setting; !setting.empty()) {
        spdlog::warn("TRISNAP_HUGE_PAGES={} is neither 0 nor 1: ignored (huge pages were chosen as without it)", setting);
    }
}

int available_cores()
{
    return std::max(1, tbb::info::default_concurrency());
}

struct ThreadLimit::Impl {
    std::unique_ptr<tbb::global_control> control;
};

ThreadLimit::ThreadLimit(int threads) : m_impl(std::make_unique<Impl>())
{
    if (threads <= 0) return;
    m_impl->control = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    CPLSetConfigOption("GDAL_NUM_THREADS", std::to_string(threads).c_str());
}

ThreadLimit::~ThreadLimit() = default;

} // namespace trisnap
