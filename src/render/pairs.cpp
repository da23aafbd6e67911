#include "render/pairs.hpp"

#include "render/grid_index.hpp"

#include <algorithm>

namespace trisnap::render {
namespace {

struct Owned {
    XY p;
    std::int64_t key;
};

struct OwnedSegment {
    Segment s;
    std::int64_t key;
};

bool less_segment(const Segment& a, const Segment& b) { return a.a < b.a || (a.a == b.a && a.b < b.b); }

std::vector<Owned> distinct_vertices(const Layer& layer)
{
    std::vector<Owned> vertices;
    for (const Shape& shape : layer.shapes)
        for (const auto& ring : shape.rings)
            for (XY p : ring) vertices.push_back({p, shape.key});
    std::sort(vertices.begin(), vertices.end(),
              [](const Owned& a, const Owned& b) { return a.p < b.p || (a.p == b.p && a.key < b.key); });
    vertices.erase(std::unique(vertices.begin(), vertices.end(), [](const Owned& a, const Owned& b) { return a.p == b.p; }),
                   vertices.end());
    return vertices;
}

std::vector<OwnedSegment> distinct_segments(const Layer& layer)
{
    std::vector<OwnedSegment> segments;
    for (const Shape& shape : layer.shapes)
        for (const auto& ring : shape.rings)
            for (std::size_t i = 1; i < ring.size(); ++i) {
                Segment s{ring[i - 1], ring[i]};
                if (s.b < s.a) std::swap(s.a, s.b);
                segments.push_back({s, shape.key});
            }
    std::sort(segments.begin(), segments.end(), [](const OwnedSegment& a, const OwnedSegment& b) {
        return less_segment(a.s, b.s) || (!less_segment(b.s, a.s) && a.key < b.key);
    });
    segments.erase(std::unique(segments.begin(), segments.end(),
                               [](const OwnedSegment& a, const OwnedSegment& b) { return a.s.a == b.s.a && a.s.b == b.s.b; }),
                   segments.end());
    return segments;
}

Site pair_site(SiteKind kind, const Owned& v, XY other, std::int64_t other_key, double d, double t)
{
    Site site;
    site.kind = kind;
    site.at = v.p;
    site.other = other;
    site.value = d;
    site.fid = v.key;
    site.fid2 = other_key;
    site.defect = kind == SiteKind::vertex_vertex ? d < t : d < t / 2;
    return site;
}

void add_vertex_vertex(const std::vector<Owned>& vertices, double t, double cell, std::vector<Site>& sites)
{
    std::vector<XY> points;
    points.reserve(vertices.size());
    for (const Owned& v : vertices) points.push_back(v.p);
    const GridIndex grid(points, cell);
    std::vector<std::uint32_t> nearest(points.size());
    std::vector<double> gap(points.size(), t);
    for (std::uint32_t i = 0; i < points.size(); ++i) {
        nearest[i] = i;
        grid.visit(points[i], t, [&](std::uint32_t j) {
            const double d = distance(points[i], points[j]);
            if (j != i && (d < gap[i] || (d == gap[i] && j < nearest[i]))) gap[i] = d, nearest[i] = j;
        });
    }
    // One site per pair: mutual nearest pairs once (from the lower index), the others from each end.
    for (std::uint32_t i = 0; i < points.size(); ++i) {
        const std::uint32_t j = nearest[i];
        if (j != i && (i < j || nearest[j] != i))
            sites.push_back(pair_site(SiteKind::vertex_vertex, vertices[i], points[j], vertices[j].key, gap[i], t));
    }
}

void add_vertex_edge(const std::vector<Owned>& vertices, const std::vector<OwnedSegment>& segments, double t,
                     double min_cell, std::vector<Site>& sites)
{
    std::vector<Segment> plain;
    plain.reserve(segments.size());
    for (const OwnedSegment& s : segments) plain.push_back(s.s);
    const GridIndex grid(plain, GridIndex::cell_for(plain, min_cell));
    for (const Owned& v : vertices) {
        double best = t;
        XY near{};
        std::int64_t key = -1;
        grid.visit(v.p, t, [&](std::uint32_t j) {
            const Segment& s = plain[j];
            if (s.a == v.p || s.b == v.p) return;
            XY q;
            const double d = distance_to_segment(v.p, s.a, s.b, &q);
            if (d < best || (d == best && key >= 0 && q < near)) best = d, near = q, key = segments[j].key;
        });
        if (key >= 0) sites.push_back(pair_site(SiteKind::vertex_edge, v, near, key, best, t));
    }
}

} // namespace

void add_pair_sites(const Layer& layer, double tolerance, std::vector<Site>& sites)
{
    const std::vector<Owned> vertices = distinct_vertices(layer);
    if (vertices.empty()) return;
    // A cell no smaller than a ten-millionth of the extent keeps cell numbers sane for a tiny T.
    const double span = std::max(layer.extent.width(), layer.extent.height());
    const double cell = std::max(tolerance, span * 1e-7);
    add_vertex_vertex(vertices, tolerance, cell, sites);
    add_vertex_edge(vertices, distinct_segments(layer), tolerance, cell, sites);
}

} // namespace trisnap::render
