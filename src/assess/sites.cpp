#include "assess/sites.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <tuple>

namespace trisnap::assess {
namespace {

/// Larger is worse for these kinds; smaller for separations; order of FIDs for the rest.
int badness_direction(SiteKind kind)
{
    switch (kind) {
    case SiteKind::missing:
    case SiteKind::overlap:
    case SiteKind::gap:
    case SiteKind::drift: return 1;
    case SiteKind::vertex_edge:
    case SiteKind::vertex_vertex: return -1;
    default: return 0;
    }
}

bool worse(const Site& a, const Site& b)
{
    if (a.kind != b.kind) {
        return a.kind < b.kind;
    }
    const int direction = badness_direction(a.kind);
    if (direction != 0 && a.value != b.value) {
        return direction > 0 ? a.value > b.value : a.value < b.value;
    }
    return std::tie(a.code, a.fid, a.fid2, a.at) < std::tie(b.code, b.fid, b.fid2, b.at);
}

/// 0: breach nobody explained; 1: breach the report explains; 2: reported problem; 3: the
/// rest, but 4: overlaps and crossings the input had already (not the snapping's doing).
int tier_of(const Site& s)
{
    if (s.breach) {
        return s.excused_by.empty() ? 0 : 1;
    }
    if (s.kind == SiteKind::problem) {
        return 2;
    }
    return s.is_new ? 3 : 4;
}

bool shares_feature(const Site& a, const Site& b)
{
    const std::array<std::int64_t, 2> fa{a.fid, a.fid2};
    for (std::int64_t f : fa) {
        if (f >= 0 && (f == b.fid || f == b.fid2)) {
            return true;
        }
    }
    return false;
}

/// Takes sites tier by tier, the kinds in turn, under the spacing and one-feature-once rules.
class Picker {
public:
    Picker(const std::vector<Site>& sites, std::size_t n, double spacing, const std::function<bool(const Site&)>& changed)
        : m_sites(sites), m_n(n), m_spacing(spacing), m_changed(changed)
    {
    }

    void take_tier(int tier)
    {
        std::array<std::size_t, k_site_kinds> next{};
        for (int k = 0; k < k_site_kinds; ++k) {
            next[static_cast<std::size_t>(k)] = first_of_kind(k);
        }
        bool progress = true;
        while (progress && picked.size() < m_n) {
            progress = false;
            for (int k = 0; k < k_site_kinds && picked.size() < m_n; ++k) {
                progress = take_next(k, tier, next[static_cast<std::size_t>(k)]) || progress;
            }
        }
    }

    std::vector<Site> picked;

private:
    std::size_t first_of_kind(int kind) const
    {
        std::size_t i = 0;
        while (i < m_sites.size() && static_cast<int>(m_sites[i].kind) < kind) {
            ++i;
        }
        return i;
    }

    bool take_next(int kind, int tier, std::size_t& i)
    {
        for (; i < m_sites.size() && static_cast<int>(m_sites[i].kind) == kind; ++i) {
            if (acceptable(m_sites[i], tier)) {
                picked.push_back(m_sites[i++]);
                return true;
            }
        }
        return false;
    }

    bool acceptable(const Site& s, int tier) const
    {
        if (tier_of(s) != tier) {
            return false;
        }
        for (const Site& p : picked) {
            if (distance(p.at, s.at) < m_spacing || shares_feature(p, s)) {
                return false;
            }
        }
        return tier < 2 || !m_changed || m_changed(s);
    }

    const std::vector<Site>& m_sites;
    std::size_t m_n;
    double m_spacing;
    const std::function<bool(const Site&)>& m_changed;
};

} // namespace

const char* site_kind_name(SiteKind kind)
{
    switch (kind) {
    case SiteKind::missing: return "missing";
    case SiteKind::invalid: return "invalid";
    case SiteKind::crossing: return "crossing";
    case SiteKind::overlap: return "overlap";
    case SiteKind::gap: return "gap";
    case SiteKind::drift: return "drift";
    case SiteKind::vertex_edge: return "vertex-edge";
    case SiteKind::vertex_vertex: return "vertex-vertex";
    case SiteKind::problem: return "problem";
    }
    return "site";
}

std::string site_code(const Site& site)
{
    return site.kind == SiteKind::problem ? std::to_string(site.code) : site_kind_name(site.kind);
}

namespace {

std::string times_t(double value, double t)
{
    const double m = value / t;
    return m >= 100 ? fmt::format("{:.0f} T", m) : fmt::format("{:.3g} T", m);
}

std::string new_or_known(const Site& s) { return s.is_new ? " (new)" : " (in the input)"; }

} // namespace

std::string describe_site(const Site& s, double t)
{
    const std::string limit = s.breach ? (s.kind == SiteKind::drift ? " (> 2T)" : s.kind == SiteKind::vertex_edge ? " (< T/2)" : " (< T)") : "";
    switch (s.kind) {
    case SiteKind::missing: return "missing: lost, size " + times_t(s.value, t);
    case SiteKind::invalid: return "invalid polygon";
    case SiteKind::crossing: return "crossing" + new_or_known(s);
    case SiteKind::overlap: return fmt::format("overlap, area {:.3g}{}", s.value, new_or_known(s));
    case SiteKind::gap: return "gap: shared boundary lost, " + times_t(s.value, t) + " long";
    case SiteKind::drift: return "drift " + times_t(s.value, t) + limit;
    case SiteKind::vertex_edge: return "vertex-edge " + times_t(s.value, t) + limit;
    case SiteKind::vertex_vertex: return "vertex-vertex " + times_t(s.value, t) + limit;
    case SiteKind::problem: return fmt::format("problem {} {}", s.code, s.name);
    }
    return "site";
}

std::string site_place(const Site& s)
{
    std::string fids = fmt::format("fid {}", s.fid);
    if (s.fid2 >= 0 && s.fid2 != s.fid) {
        fids += fmt::format(" / {}", s.fid2);
    }
    return fmt::format("{} at {:.10g}, {:.10g}", fids, s.at.x, s.at.y);
}

void sort_sites(std::vector<Site>& sites) { std::stable_sort(sites.begin(), sites.end(), worse); }

std::vector<Site> pick_worst(const std::vector<Site>& sites, std::size_t n, double spacing,
                             const std::function<bool(const Site&)>& changed)
{
    Picker picker(sites, n, spacing, changed);
    for (int tier = 0; tier < 5; ++tier) {
        picker.take_tier(tier);
    }
    return picker.picked;
}

} // namespace trisnap::assess
