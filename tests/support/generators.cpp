#include "generators.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trisnap {

double uniform(std::mt19937_64& rng, double lo, double hi) {
    const double unit = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    return lo + (hi - lo) * unit;
}

std::int64_t uniform_int(std::mt19937_64& rng, std::int64_t lo, std::int64_t hi) {
    const auto span = static_cast<std::uint64_t>(hi - lo) + 1;
    return lo + static_cast<std::int64_t>(span == 0 ? rng() : rng() % span);
}

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

Coord at(double x, double y) {
    return Coord{x, y};
}

Feature polygon_feature(std::int64_t id, std::vector<Path> rings) {
    Feature f;
    f.id = id;
    f.geometry.type = Geometry::Type::Polygon;
    f.geometry.polygons.push_back(Polygon{std::move(rings)});
    return f;
}

void close_ring(Path& ring) {
    ring.push_back(ring.front());
}

/// Corners of the coverage grid, (nx+1) x (ny+1), row-major by j then i.
std::vector<Coord> grid_corners(int nx, int ny, double cell, double jitter, std::mt19937_64& rng) {
    std::vector<Coord> corners;
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
            // Draw both offsets always, so the sequence does not depend on the border logic.
            const double dx = uniform(rng, -jitter, jitter) * cell;
            const double dy = uniform(rng, -jitter, jitter) * cell;
            corners.push_back(at(i * cell + (i > 0 && i < nx ? dx : 0.0),
                                 j * cell + (j > 0 && j < ny ? dy : 0.0)));
        }
    }
    return corners;
}

/// Interior vertices of the edge a -> b: sorted positions along it, wiggled sideways.
Path edge_points(const Coord& a, const Coord& b, int count, double wiggle, std::mt19937_64& rng) {
    std::vector<double> along(static_cast<std::size_t>(count));
    for (double& u : along)
        u = uniform(rng, 0.05, 0.95);
    std::sort(along.begin(), along.end());
    const double dx = b.x - a.x, dy = b.y - a.y, len = std::hypot(dx, dy);
    Path points;
    for (double u : along) {
        const double side = uniform(rng, -wiggle, wiggle);
        points.push_back(at(a.x + u * dx - side * dy / len, a.y + u * dy + side * dx / len));
    }
    return points;
}

/// Extra points of every horizontal edge (i, j) -> (i+1, j), then of every vertical edge
/// (i, j) -> (i, j+1); border edges are not wiggled so the union stays the rectangle.
struct CoverageEdges {
    std::vector<Path> horizontal; ///< index j * nx + i
    std::vector<Path> vertical;   ///< index j * (nx + 1) + i
};

CoverageEdges coverage_edges(int nx, int ny, const std::vector<Coord>& corners, int count,
                             double wiggle, std::mt19937_64& rng) {
    auto corner = [&](int i, int j) { return corners[static_cast<std::size_t>(j * (nx + 1) + i)]; };
    CoverageEdges edges;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i < nx; ++i)
            edges.horizontal.push_back(edge_points(corner(i, j), corner(i + 1, j), count,
                                                   j == 0 || j == ny ? 0.0 : wiggle, rng));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i <= nx; ++i)
            edges.vertical.push_back(edge_points(corner(i, j), corner(i, j + 1), count,
                                                 i == 0 || i == nx ? 0.0 : wiggle, rng));
    return edges;
}

void append(Path& ring, const Path& points, bool reversed) {
    if (reversed)
        ring.insert(ring.end(), points.rbegin(), points.rend());
    else
        ring.insert(ring.end(), points.begin(), points.end());
}

} // namespace

Feature square(std::int64_t id, double x0, double y0, double size) {
    Path ring{at(x0, y0), at(x0 + size, y0), at(x0 + size, y0 + size), at(x0, y0 + size)};
    close_ring(ring);
    return polygon_feature(id, {std::move(ring)});
}

Feature dense_line(std::int64_t id, int n, double spacing, double wiggle, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    Feature f;
    f.id = id;
    f.geometry.type = Geometry::Type::LineString;
    Path line;
    for (int i = 0; i < n; ++i)
        line.push_back(at(i * spacing, uniform(rng, -wiggle, wiggle)));
    f.geometry.lines.push_back(std::move(line));
    return f;
}

std::vector<Feature> vertex_cluster(int k, double t, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Feature> out;
    const double sector = two_pi / k;
    for (int i = 0; i < k; ++i) {
        // The apex stays inside the sector's inner part, so neighbours cannot cross.
        const double r = uniform(rng, 0.0, 0.5 * t);
        const double a = sector * (i + uniform(rng, 0.3, 0.7));
        const double a0 = sector * (i + 0.1), a1 = sector * (i + 0.9);
        const double far = 10.0 * t * uniform(rng, 0.9, 1.1);
        Path ring{at(r * std::cos(a), r * std::sin(a)), at(far * std::cos(a0), far * std::sin(a0)),
                  at(far * std::cos(a1), far * std::sin(a1))};
        close_ring(ring);
        out.push_back(polygon_feature(i + 1, {std::move(ring)}));
    }
    return out;
}

std::vector<Feature> perturbed_grid_coverage(int nx, int ny, double cell, double jitter,
                                             std::uint64_t seed, int points_per_edge,
                                             double edge_wiggle) {
    std::mt19937_64 rng(seed);
    const std::vector<Coord> corners = grid_corners(nx, ny, cell, jitter, rng);
    const CoverageEdges edges =
        coverage_edges(nx, ny, corners, points_per_edge, edge_wiggle * cell, rng);
    auto corner = [&](int i, int j) { return corners[static_cast<std::size_t>(j * (nx + 1) + i)]; };
    auto h = [&](int i, int j) -> const Path& { return edges.horizontal[static_cast<std::size_t>(j * nx + i)]; };
    auto v = [&](int i, int j) -> const Path& { return edges.vertical[static_cast<std::size_t>(j * (nx + 1) + i)]; };
    std::vector<Feature> cells;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            // Counter-clockwise: bottom, right, top (reversed), left (reversed).
            Path ring{corner(i, j)};
            append(ring, h(i, j), false);
            ring.push_back(corner(i + 1, j));
            append(ring, v(i + 1, j), false);
            ring.push_back(corner(i + 1, j + 1));
            append(ring, h(i, j + 1), true);
            ring.push_back(corner(i, j + 1));
            append(ring, v(i, j), true);
            close_ring(ring);
            cells.push_back(polygon_feature(j * nx + i + 1, {std::move(ring)}));
        }
    }
    return cells;
}

std::size_t vertex_count(const std::vector<Feature>& features) {
    std::size_t n = 0;
    for (const Feature& f : features) {
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& r : p.rings)
                n += r.size();
        for (const Path& l : f.geometry.lines)
            n += l.size();
    }
    return n;
}

} // namespace trisnap
