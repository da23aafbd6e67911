#include "io/gdal_errors.hpp"

#include <cpl_error.h>

#include <cctype>

namespace trisnap {
namespace {

void CPL_STDCALL capture_handler(CPLErr severity, CPLErrorNum, const char* message)
{
    auto* capture = static_cast<ScopedErrorCapture*>(CPLGetErrorHandlerUserData());
    if (capture) capture->record(static_cast<int>(severity), message);
}

} // namespace

ScopedErrorCapture::ScopedErrorCapture()
{
    CPLPushErrorHandlerEx(capture_handler, this);
    CPLSetCurrentErrorHandlerCatchDebug(FALSE); // CPLDebug lines go on to the process handler (-vv)
}

ScopedErrorCapture::~ScopedErrorCapture() { CPLPopErrorHandler(); }

void ScopedErrorCapture::record(int severity, const char* message)
{
    // Some drivers end their message with a newline or spread it over several (PostgreSQL);
    // errors here are one line, so runs of white space become one space.
    std::string text;
    for (const char* c = message ? message : ""; *c != '\0'; ++c) {
        const bool space = std::isspace(static_cast<unsigned char>(*c)) != 0;
        if (!space) {
            text += *c;
        } else if (!text.empty() && text.back() != ' ') {
            text += ' ';
        }
    }
    if (!text.empty() && text.back() == ' ') {
        text.pop_back();
    }
    if (severity >= CE_Failure) m_errors.push_back(text);
    else if (severity == CE_Warning) m_warnings.push_back(text);
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
