#include "assess/excuses.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <span>

namespace trisnap::assess {
namespace {

constexpr std::array k_missing{106, 107, 108, 109, 110, 201, 202, 303, 901, 902};
constexpr std::array k_drift{103, 104, 105, 203, 204, 206, 208, 209};
constexpr std::array k_gap{203, 204, 208, 209, 210};
constexpr std::array k_separation{205, 207};

std::span<const int> codes_for(Defect defect)
{
    switch (defect) {
    case Defect::missing: return k_missing;
    case Defect::drift: return k_drift;
    case Defect::gap: return k_gap;
    }
    return {};
}

bool contains(std::span<const int> codes, int code) { return std::find(codes.begin(), codes.end(), code) != codes.end(); }

void append(std::string& text, int code, const std::string& name)
{
    const std::string item = fmt::format("{} {}", code, name);
    if (text.find(item) != std::string::npos) {
        return;
    }
    text += text.empty() ? item : ", " + item;
}

} // namespace

Excuses::Excuses(const SnapReport& report)
{
    for (const ReportedProblem& p : report.problems) {
        m_by_fid.push_back({p.fid, p.code, p.name});
        if (contains(k_separation, p.code) && p.at) {
            m_located.push_back(p);
        }
    }
    std::sort(m_by_fid.begin(), m_by_fid.end(), [](const Entry& a, const Entry& b) {
        return a.fid < b.fid || (a.fid == b.fid && a.code < b.code);
    });
}

std::string Excuses::explain(Defect defect, std::int64_t fid) const
{
    const auto first = std::lower_bound(m_by_fid.begin(), m_by_fid.end(), fid,
                                        [](const Entry& e, std::int64_t f) { return e.fid < f; });
    std::string text;
    for (auto it = first; it != m_by_fid.end() && it->fid == fid; ++it) {
        if (contains(codes_for(defect), it->code)) {
            append(text, it->code, it->name);
        }
    }
    return text;
}

std::string Excuses::explain(Defect defect, std::int64_t fid_a, std::int64_t fid_b) const
{
    std::string text = explain(defect, fid_a);
    const std::string other = explain(defect, fid_b);
    if (!other.empty()) {
        text += text.empty() ? other : "; " + other;
    }
    return text;
}

std::string Excuses::explain_separation(Pt p, Pt q, double radius) const
{
    std::string text;
    for (const ReportedProblem& problem : m_located) {
        if (distance(*problem.at, p) <= radius || distance(*problem.at, q) <= radius) {
            append(text, problem.code, problem.name);
        }
    }
    return text;
}

} // namespace trisnap::assess
