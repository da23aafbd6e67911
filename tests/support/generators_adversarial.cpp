// Inputs that make snapping expensive when the engine is not careful: a tolerance larger than
// the features (everything merges into clusters), and many vertices closer than t along a
// straight line or an exact circle (long chains of merges around vertices of high degree).
#include "generators.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trisnap {
namespace {

Feature polygon_of(std::int64_t id, Path ring) {
    ring.push_back(ring.front());
    Feature f;
    f.id = id;
    f.geometry.type = Geometry::Type::Polygon;
    f.geometry.polygons.push_back(Polygon{{std::move(ring)}});
    return f;
}

} // namespace

std::vector<Feature> random_small_squares(int n, double side, double extent, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Feature> out;
    for (int i = 0; i < n; ++i) {
        const double x = uniform(rng, 0.0, extent);
        const double y = uniform(rng, 0.0, extent);
        out.push_back(square(i + 1, x, y, side));
    }
    return out;
}

Feature densified_square(std::int64_t id, int n, double side) {
    const int per_side = std::max(1, n / 4);
    const double step = side / per_side;
    Path ring;
    for (int k = 0; k < per_side; ++k) {
        ring.push_back(Coord{k * step, 0.0});
    }
    for (int k = 0; k < per_side; ++k) {
        ring.push_back(Coord{side, k * step});
    }
    for (int k = 0; k < per_side; ++k) {
        ring.push_back(Coord{side - k * step, side});
    }
    for (int k = 0; k < per_side; ++k) {
        ring.push_back(Coord{0.0, side - k * step});
    }
    return polygon_of(id, std::move(ring));
}

Feature circle(std::int64_t id, int n, double radius, double jitter, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    Path ring;
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * k / n;
        const double dx = jitter > 0 ? uniform(rng, -jitter, jitter) : 0.0;
        const double dy = jitter > 0 ? uniform(rng, -jitter, jitter) : 0.0;
        ring.push_back(Coord{radius * std::cos(a) + dx, radius * std::sin(a) + dy});
    }
    return polygon_of(id, std::move(ring));
}

} // namespace trisnap

namespace trisnap {

std::vector<AdversarialCase> adversarial_cases(double scale) {
    const auto scaled = [scale](int n) { return std::max(8, static_cast<int>(std::lround(n * scale))); };
    std::vector<AdversarialCase> out;
    // Squares of side 1 in a box about 1.5 t wide per 100 squares: at t = 10 each square collapses
    // and all of them merge into a few clusters.
    for (int n : {100, 200, 400}) {
        const int k = scaled(n);
        out.push_back({"squares", random_small_squares(k, 1.0, 15.0 * std::sqrt(k / 100.0), 7), 0.01, 10.0});
    }
    // Spacing 100 / (n / 4): 0.004 at n = 100 k, under t = 0.01.
    out.push_back({"densified_square", {densified_square(1, scaled(100'000), 100.0 * scale)}, 1e-4, 0.01});
    // Spacing 2 pi 50 / n: 0.0079 at n = 40 k.
    out.push_back({"circle", {circle(1, scaled(40'000), 50.0 * scale, 0.0, 3)}, 1e-4, 0.01});
    out.push_back({"circle_jittered", {circle(1, scaled(100'000), 125.0 * scale, 0.003 * scale, 3)}, 1e-4, 0.01});
    // Spacing 2 pi 20 / 200 k = 6.3e-4, sixteen vertices per t: merged vertices become hubs of
    // the circle's inside (core/mesh_hubs.cpp).
    out.push_back({"circle_dense", {circle(1, scaled(200'000), 20.0 * scale, 0.0, 1)}, 1e-4, 0.01});
    // Squares packed ever denser in one 30 x 30 box (scale 1: 2,000 of them, 9 vertices per unit
    // square), inside a frame whose four edges are 110 long. Only an edge longer than about 1.7 t
    // can give a split, so the nearest-only walks shrank below the edge radius only while no such
    // edge existed anywhere: with the frame, every walk at t = 10 covered the disk of radius 5
    // (hundreds of vertices), the way NJ shore's few sea edges made 0.1 degrees take > 300 s.
    {
        std::vector<Feature> framed = random_small_squares(scaled(2000), 1.0, 30.0, 11);
        Feature frame;
        frame.id = static_cast<std::int64_t>(framed.size()) + 1;
        frame.geometry.type = Geometry::Type::LineString;
        frame.geometry.lines.push_back(Path{{-40, -40}, {70, -40}, {70, 70}, {-40, 70}, {-40, -40}});
        framed.push_back(std::move(frame));
        out.push_back({"squares_framed", std::move(framed), 0.01, 10.0});
    }
    return out;
}

} // namespace trisnap
