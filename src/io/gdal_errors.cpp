#include "io/gdal_errors.hpp"

#include <cpl_error.h>

namespace trisnap {
namespace {

void CPL_STDCALL capture_handler(CPLErr severity, CPLErrorNum, const char* message)
{
    auto* capture = static_cast<ScopedErrorCapture*>(CPLGetErrorHandlerUserData());
    if (capture) capture->record(static_cast<int>(severity), message);
}

} // namespace

ScopedErrorCapture::ScopedErrorCapture() { CPLPushErrorHandlerEx(capture_handler, this); }

ScopedErrorCapture::~ScopedErrorCapture() { CPLPopErrorHandler(); }

void ScopedErrorCapture::record(int severity, const char* message)
{
    std::string text = message ? message : "";
    // Some drivers end their messages with a newline; ours are one line each.
    text.erase(text.find_last_not_of(" \n\r\t") + 1);
    if (severity >= CE_Failure) {
        m_errors.push_back(text);
    } else if (severity == CE_Warning) {
        m_warnings.push_back(text);
    }
}

std::string ScopedErrorCapture::last_error(const std::string& fallback) const
{
    return m_errors.empty() ? fallback : m_errors.back();
}

void ScopedErrorCapture::clear()
{
    m_errors.clear();
    m_warnings.clear();
}

} // namespace trisnap
