// The report's examples as sites, and the worst of them (the order shared with render).
#include "assess/measures.hpp"
#include "assess/str_tree.hpp"

#include <array>
#include <cmath>

namespace trisnap::assess {
namespace {

Site site_of(SiteKind kind, const AssessExample& e, bool breach)
{
    Site s;
    s.kind = kind;
    s.at = {e.x, e.y};
    s.other = s.at;
    s.value = e.value;
    s.fid = e.fid_a;
    s.fid2 = e.fid_b;
    s.breach = breach;
    s.excused_by = e.excused_by;
    s.is_new = e.is_new;
    return s;
}

Site pair_site(SiteKind kind, const AssessExample& e, bool breach)
{
    Site s = site_of(kind, e, breach);
    s.other = {e.x2, e.y2};
    return s;
}

void add_measured(const AssessReport& r, std::vector<Site>& sites)
{
    const double t = r.tolerance;
    for (const AssessExample& e : r.missing) {
        Site s = site_of(SiteKind::missing, e, true);
        s.fid2 = -1;
        s.extent = Box{e.edge[0], e.edge[1], e.edge[2], e.edge[3]};
        sites.push_back(s);
    }
    for (const AssessExample& e : r.invalid) {
        if (std::isfinite(e.x)) { // unmeasurable outputs have no place to show
            sites.push_back(site_of(SiteKind::invalid, e, true));
        }
    }
    for (const AssessExample& e : r.crossings) {
        sites.push_back(site_of(SiteKind::crossing, e, e.is_new));
    }
    for (const AssessExample& e : r.overlaps) {
        sites.push_back(site_of(SiteKind::overlap, e, e.is_new));
    }
    for (const AssessExample& e : r.gaps_new_examples) {
        sites.push_back(site_of(SiteKind::gap, e, true));
    }
    for (const AssessExample& e : r.largest_hausdorff) {
        if (e.value > 0) {
            sites.push_back(pair_site(SiteKind::drift, e, e.value > 2 * t));
        }
    }
    for (const AssessExample& e : r.closest_vertex_edge) {
        sites.push_back(pair_site(SiteKind::vertex_edge, e, e.value < t / 2));
    }
    for (const AssessExample& e : r.closest_vertex_vertex) {
        sites.push_back(pair_site(SiteKind::vertex_vertex, e, e.value < t));
    }
}

/// Whether the two layers differ near a place: their segments meeting a square window, compared.
/// Segments are indexed one by one (a feature can be a continent of 10^5 edges).
class ChangeTest {
public:
    ChangeTest(const LayerData& a, const LayerData& b, double radius) : m_a(a), m_b(b), m_radius(radius) {}
    bool changed(Pt p) const
    {
        const Box window{p.x - m_radius, p.y - m_radius, p.x + m_radius, p.y + m_radius};
        return m_a.near(window) != m_b.near(window);
    }

private:
    using Key = std::array<double, 4>;

    struct Indexed {
        std::vector<Key> segments; // (x1, y1, x2, y2) with the lower end first
        StrTree tree;

        explicit Indexed(const LayerData& d)
        {
            std::vector<Box> boxes;
            for (std::size_t i = 0; i < d.parts.size(); ++i) {
                for (std::uint32_t k = d.parts[i].begin; k + 1 < d.parts[i].end; ++k) {
                    const Pt p = std::min(d.pts[k], d.pts[k + 1]);
                    const Pt q = std::max(d.pts[k], d.pts[k + 1]);
                    if (p != q) {
                        segments.push_back({p.x, p.y, q.x, q.y});
                        boxes.push_back(segment_box(p, q));
                    }
                }
            }
            tree.build(std::move(boxes));
        }

        std::vector<Key> near(const Box& window) const
        {
            std::vector<Key> out;
            tree.query(window, [&](std::uint32_t id) { out.push_back(segments[id]); });
            std::sort(out.begin(), out.end());
            out.erase(std::unique(out.begin(), out.end()), out.end());
            return out;
        }
    };

    Indexed m_a;
    Indexed m_b;
    double m_radius;
};

} // namespace

void measure_worst(const Context& c, std::size_t n, AssessReport& r)
{
    keep_first(r.excused, c.k, by_fids);
    const ChangeTest test(c.a, c.b, 3 * c.tolerance);
    r.worst = pick_worst(report_sites(r), n, 3 * c.tolerance, [&](const Site& s) { return test.changed(s.at); });
}

} // namespace trisnap::assess

namespace trisnap {

std::vector<assess::Site> report_sites(const AssessReport& r)
{
    std::vector<assess::Site> sites;
    assess::add_measured(r, sites);
    for (const AssessExample& e : r.problems) {
        assess::Site s = assess::site_of(assess::SiteKind::problem, e, false);
        s.code = static_cast<int>(e.value);
        s.name = e.text;
        s.value = 0;
        s.fid2 = -1;
        sites.push_back(s);
    }
    assess::sort_sites(sites);
    return sites;
}

} // namespace trisnap
