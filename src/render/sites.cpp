#include "render/sites.hpp"

#include "render/grid_index.hpp"
#include "render/pairs.hpp"

#include <algorithm>
#include <cmath>

namespace trisnap::render {
namespace {

std::vector<Segment> segments_of(const Shape& shape)
{
    std::vector<Segment> segments;
    for (const auto& ring : shape.rings)
        for (std::size_t i = 1; i < ring.size(); ++i) segments.push_back({ring[i - 1], ring[i]});
    return segments;
}

/// Nearest point of `segments` to p: grows the search radius until the best hit lies inside it.
double nearest_on(const std::vector<Segment>& segments, const GridIndex& grid, XY p, double limit, XY& near)
{
    double best = std::numeric_limits<double>::infinity();
    auto consider = [&](std::uint32_t i) {
        XY q;
        const double d = distance_to_segment(p, segments[i].a, segments[i].b, &q);
        if (d < best || (d == best && q < near)) best = d, near = q;
    };
    // Widen while the cells to visit stay fewer than the segments; then scanning all is cheaper.
    for (double r = grid.cell(); r <= limit; r *= 2) {
        const double cells = std::pow(2 * r / grid.cell() + 1, 2);
        if (cells > static_cast<double>(segments.size()) + 9) break;
        grid.visit(p, r, consider);
        if (best <= r) return best;
    }
    for (std::uint32_t i = 0; i < segments.size(); ++i) consider(i);
    return best;
}

/// Largest distance from a vertex of `from` to the boundary of `to`.
double directed_drift(const Shape& from, const Shape& to, XY& at, XY& near)
{
    const std::vector<Segment> segments = segments_of(to);
    Box both = from.box;
    both.add(to.box);
    const double span = std::max(both.width(), both.height());
    const GridIndex grid(segments, GridIndex::cell_for(segments, std::max(span * 1e-6, 1e-300)));
    double worst = 0;
    for (const auto& ring : from.rings)
        for (XY p : ring) {
            XY q;
            const double d = nearest_on(segments, grid, p, 2 * span + grid.cell(), q);
            if (d > worst) worst = d, at = p, near = q;
        }
    return worst;
}

Site drift_site(const Shape& in, const Shape& out, std::optional<double> tolerance)
{
    Site site;
    site.kind = SiteKind::drift;
    site.fid = site.fid2 = in.key;
    XY at, near;
    const double forward = directed_drift(out, in, site.at, site.other);
    const double back = directed_drift(in, out, at, near);
    site.value = forward;
    if (back > forward) site.value = back, site.at = near, site.other = at; // `at` stays on the output
    site.defect = tolerance && site.value > 2 * *tolerance;
    return site;
}

double mean_width(const Shape& shape)
{
    double area = 0, length = 0;
    for (const auto& ring : shape.rings) {
        double twice = 0;
        for (std::size_t i = 1; i < ring.size(); ++i) {
            twice += ring[i - 1].x * ring[i].y - ring[i].x * ring[i - 1].y;
            length += distance(ring[i - 1], ring[i]);
        }
        area += std::abs(twice) / 2;
    }
    if (!shape.polygon) return length;
    return length > 0 ? 2 * area / length : 0.0;
}

Site collapse_site(const Shape& in)
{
    Site site;
    site.kind = SiteKind::collapse;
    site.at = site.other = in.box.centre();
    site.fid = in.key;
    site.value = mean_width(in);
    site.name = in.polygon ? "width" : "length";
    site.extent = in.box;
    site.defect = true;
    return site;
}

void add_layer_sites(const Layer& in, const Layer& out, std::optional<double> tolerance, std::vector<Site>& sites)
{
    std::size_t j = 0;
    for (const Shape& a : in.shapes) {
        while (j < out.shapes.size() && out.shapes[j].key < a.key) ++j;
        if (j < out.shapes.size() && out.shapes[j].key == a.key) {
            Site site = drift_site(a, out.shapes[j++], tolerance);
            if (site.value > 0) sites.push_back(site);
        } else {
            sites.push_back(collapse_site(a));
        }
    }
}

bool worse(const Site& a, const Site& b)
{
    if (a.kind != b.kind) return a.kind < b.kind;
    switch (a.kind) {
    case SiteKind::collapse:
    case SiteKind::drift:
        if (a.value != b.value) return a.value > b.value;
        break;
    case SiteKind::vertex_edge:
    case SiteKind::vertex_vertex:
        if (a.value != b.value) return a.value < b.value;
        break;
    case SiteKind::problem:
        if (a.code != b.code) return a.code < b.code;
        break;
    }
    if (a.fid != b.fid) return a.fid < b.fid;
    return a.at < b.at;
}

} // namespace

const char* kind_name(SiteKind kind)
{
    switch (kind) {
    case SiteKind::collapse: return "collapse";
    case SiteKind::drift: return "drift";
    case SiteKind::vertex_edge: return "vertex-edge";
    case SiteKind::vertex_vertex: return "vertex-vertex";
    case SiteKind::problem: return "problem";
    }
    return "site";
}

std::vector<Site> find_sites(const Layer& in, const Layer* out, std::optional<double> tolerance,
                             std::vector<Site> problems)
{
    std::vector<Site> sites = std::move(problems);
    if (out) add_layer_sites(in, *out, tolerance, sites);
    if (tolerance) add_pair_sites(out ? *out : in, *tolerance, sites);
    std::stable_sort(sites.begin(), sites.end(), worse);
    return sites;
}

std::vector<Site> pick_worst(const std::vector<Site>& sites, std::size_t n, double spacing)
{
    std::vector<Site> picked;
    auto far_enough = [&](const Site& s) {
        return std::none_of(picked.begin(), picked.end(), [&](const Site& p) { return distance(p.at, s.at) < spacing; });
    };
    for (bool defects : {true, false}) {
        std::vector<std::size_t> next(k_site_kinds, 0); // per kind, the next index of `sites` to try
        std::size_t first = 0;
        for (int k = 0; k < k_site_kinds; ++k) {
            while (first < sites.size() && static_cast<int>(sites[first].kind) < k) ++first;
            next[static_cast<std::size_t>(k)] = first;
        }
        for (bool progress = true; progress && picked.size() < n;) {
            progress = false;
            for (int k = 0; k < k_site_kinds && picked.size() < n; ++k) {
                std::size_t& i = next[static_cast<std::size_t>(k)];
                while (i < sites.size() && static_cast<int>(sites[i].kind) == k &&
                       (sites[i].defect != defects || !far_enough(sites[i])))
                    ++i;
                if (i < sites.size() && static_cast<int>(sites[i].kind) == k) {
                    picked.push_back(sites[i++]);
                    progress = true;
                }
            }
        }
    }
    return picked;
}

double panel_half_size(const Site& site, double tolerance)
{
    const double t = tolerance;
    switch (site.kind) {
    case SiteKind::collapse: return std::max(site.extent.width(), site.extent.height()) * 0.75 + 4 * t;
    case SiteKind::drift: return std::max(6 * t, 2.5 * site.value);
    case SiteKind::vertex_edge:
    case SiteKind::vertex_vertex: return std::max(6 * t, 5 * site.value);
    case SiteKind::problem: return 8 * t;
    }
    return 8 * t;
}

} // namespace trisnap::render
