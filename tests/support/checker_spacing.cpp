// Vertex-vertex and vertex-edge spacing of the output, by exact coordinates: the same coordinate
// in two features (a shared boundary) or twice in a ring (its closing point) is one vertex.
#include "checker_detail.hpp"
#include "checker_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace trisnap::checker_detail {
namespace {

bool by_coords(const Segment& a, const Segment& b) {
    return std::tie(a.ax, a.ay, a.bx, a.by) < std::tie(b.ax, b.ay, b.bx, b.by);
}

bool same_coords(const Segment& a, const Segment& b) {
    return a.ax == b.ax && a.ay == b.ay && a.bx == b.bx && a.by == b.by;
}

void sort_unique(std::vector<Segment>& items) {
    std::sort(items.begin(), items.end(), by_coords);
    items.erase(std::unique(items.begin(), items.end(), same_coords), items.end());
}

/// Distinct output vertices as zero-length segments, so SegmentGrid can index them.
std::vector<Segment> distinct_vertices(const Side& out) {
    std::vector<Segment> points;
    points.reserve(2 * out.segments.size());
    for (const Segment& s : out.segments) {
        points.push_back(Segment{s.ax, s.ay, s.ax, s.ay, s.feature});
        points.push_back(Segment{s.bx, s.by, s.bx, s.by, s.feature});
    }
    sort_unique(points);
    return points;
}

/// Distinct undirected output segments: a boundary shared by two features is one edge.
std::vector<Segment> distinct_edges(const Side& out) {
    std::vector<Segment> edges = out.segments;
    for (Segment& s : edges)
        if (std::tie(s.bx, s.by) < std::tie(s.ax, s.ay)) {
            std::swap(s.ax, s.bx);
            std::swap(s.ay, s.by);
        }
    sort_unique(edges);
    return edges;
}

/// Same allowance for floating point as ContractReport::ok(), so counts agree with it.
constexpr double slack = 1.0 - 1e-9;

std::int64_t id_of(const Side& side, const Segment& s) {
    return side.features[s.feature].id;
}

void vertex_vertex(const Side& out, const std::vector<Segment>& points, double t,
                   ContractReport& report, Examples& examples) {
    const double radius = 2.0 * t;
    SegmentGrid grid(points, radius);
    for (std::uint32_t i = 0; i < points.size(); ++i) {
        const Segment& p = points[i];
        grid.visit_near(p.ax, p.ay, radius, [&](std::uint32_t j) {
            if (j <= i)
                return;
            const Segment& q = points[j];
            const double d = std::hypot(q.ax - p.ax, q.ay - p.ay);
            if (d <= radius)
                report.min_vertex_vertex = std::min(report.min_vertex_vertex, d);
            if (d >= t * slack)
                return;
            ++report.n_close_vertex_pairs;
            examples.add("vertex-vertex",
                         "vertex-vertex " + distance_text(d, t) + ": id " +
                             std::to_string(id_of(out, p)) + " " + point_text(p.ax, p.ay) +
                             ", id " + std::to_string(id_of(out, q)) + " " +
                             point_text(q.ax, q.ay));
        });
    }
}

void vertex_edge(const Side& out, const std::vector<Segment>& points, double t,
                 double edge_factor, ContractReport& report, Examples& examples) {
    const double radius = 2.0 * t;
    const std::vector<Segment> edges = distinct_edges(out);
    SegmentGrid grid(edges, radius);
    for (const Segment& p : points) {
        grid.visit_near(p.ax, p.ay, radius, [&](std::uint32_t j) {
            const Segment& e = edges[j];
            if ((p.ax == e.ax && p.ay == e.ay) || (p.ax == e.bx && p.ay == e.by))
                return;
            const double d = point_segment_distance(p.ax, p.ay, e);
            if (d <= radius)
                report.min_vertex_edge = std::min(report.min_vertex_edge, d);
            if (d >= edge_factor * t * slack)
                return;
            ++report.n_close_vertex_edge;
            examples.add("vertex-edge",
                         "vertex-edge " + distance_text(d, t) + ": vertex of id " +
                             std::to_string(id_of(out, p)) + " " + point_text(p.ax, p.ay) +
                             ", edge of id " + std::to_string(id_of(out, e)) + " " +
                             point_text(e.ax, e.ay) + "-" + point_text(e.bx, e.by));
        });
    }
}

} // namespace

void measure_spacing(const Side& out, double t, double edge_factor, ContractReport& report,
                     Examples& examples) {
    report.min_vertex_vertex = std::numeric_limits<double>::infinity();
    report.min_vertex_edge = std::numeric_limits<double>::infinity();
    const std::vector<Segment> points = distinct_vertices(out);
    vertex_vertex(out, points, t, report, examples);
    vertex_edge(out, points, t, edge_factor, report, examples);
}

} // namespace trisnap::checker_detail
