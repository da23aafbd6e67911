// near_degenerate_polygons: star-shaped rings (vertices sorted by angle around a centre, so
// every ring is simple whatever the radii) with the defects snapping has to resolve.
#include "generators.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trisnap {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

struct Polar {
    double angle;
    double radius;
};

struct Star {
    Coord centre;
    std::vector<Polar> vertices; ///< strictly increasing angles within one turn
};

Path ring_of(const Star& star) {
    Path ring;
    for (const Polar& p : star.vertices)
        ring.push_back(Coord{star.centre.x + p.radius * std::cos(p.angle),
                             star.centre.y + p.radius * std::sin(p.angle)});
    ring.push_back(ring.front());
    return ring;
}

/// Angular room after vertex m (to the next one, wrapping around).
double gap_after(const Star& star, std::size_t m) {
    const std::size_t n = star.vertices.size();
    const double next = m + 1 < n ? star.vertices[m + 1].angle : star.vertices[0].angle + two_pi;
    return next - star.vertices[m].angle;
}

Star random_star(Coord centre, double radius, double first_angle, std::mt19937_64& rng) {
    Star star{centre, {}};
    const auto k = uniform_int(rng, 8, 14);
    // Each vertex stays in its own 1/k of the turn (jittered over 80% of it), so gaps stay
    // below 1.8/k of a turn and the ring keeps a fat core for holes.
    for (std::int64_t i = 0; i < k; ++i) {
        const double u = i == 0 ? 0.0 : uniform(rng, 0.0, 0.8);
        star.vertices.push_back(Polar{first_angle + two_pi * (static_cast<double>(i) + u) / k,
                                      radius * (i == 0 ? 1.0 : uniform(rng, 0.6, 1.0))});
    }
    return star;
}

/// A vertex 0.1t..0.5t after an existing one.
void add_near_coincident(Star& star, double t, std::mt19937_64& rng) {
    const auto m = static_cast<std::size_t>(uniform_int(rng, 0, star.vertices.size() - 1));
    const Polar p = star.vertices[m];
    const double d = uniform(rng, 0.1, 0.5) * t;
    const double turn = std::min(uniform(rng, 0.2, 1.0) * d / p.radius, 0.5 * gap_after(star, m));
    const double radius = std::max(p.radius + uniform(rng, -0.5, 0.5) * d, 0.5 * p.radius);
    star.vertices.insert(star.vertices.begin() + static_cast<std::ptrdiff_t>(m + 1),
                         Polar{p.angle + turn, radius});
}

/// A spike 2..4 radii long whose base is 0.2t..2t wide.
void add_spike(Star& star, double radius, double t, std::mt19937_64& rng) {
    const auto m = static_cast<std::size_t>(uniform_int(rng, 0, star.vertices.size() - 1));
    const double gap = gap_after(star, m);
    const double mid = star.vertices[m].angle + 0.5 * gap;
    const std::size_t next = (m + 1) % star.vertices.size();
    const double base = 0.9 * std::min(star.vertices[m].radius, star.vertices[next].radius);
    const double half = std::min(0.5 * uniform(rng, 0.2, 2.0) * t / base, 0.2 * gap);
    const Polar spike[3] = {{mid - half, base}, {mid, radius * uniform(rng, 2.0, 4.0)},
                            {mid + half, base}};
    star.vertices.insert(star.vertices.begin() + static_cast<std::ptrdiff_t>(m + 1), spike,
                         spike + 3);
}

/// A clockwise hexagon around the centre, well inside the star's core (see random_star).
Path hole(const Coord& centre, double radius, std::mt19937_64& rng) {
    const double r = radius * uniform(rng, 0.1, 0.3);
    Path ring;
    for (int i = 6; i > 0; --i)
        ring.push_back(Coord{centre.x + r * std::cos(two_pi * i / 6),
                             centre.y + r * std::sin(two_pi * i / 6)});
    ring.push_back(ring.front());
    return ring;
}

Path sliver(double scale, double t, std::mt19937_64& rng) {
    const double cx = uniform(rng, 0.0, scale), cy = uniform(rng, 0.0, scale);
    const double half_len = 0.5 * uniform(rng, 10.0, 50.0) * t;
    const double half_w = 0.5 * uniform(rng, 0.1, 0.9) * t;
    const double a = uniform(rng, 0.0, two_pi);
    const double ux = std::cos(a), uy = std::sin(a);
    Path ring;
    const std::pair<double, double> corners[4] = {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}};
    for (const auto& [s, w] : corners)
        ring.push_back(Coord{cx + s * half_len * ux - w * half_w * uy,
                             cy + s * half_len * uy + w * half_w * ux});
    ring.push_back(ring.front());
    return ring;
}

/// Centre and first angle that put vertex 0 of a new star 0.1t..0.5t outside an edge of
/// `ring` (counter-clockwise), facing it.
std::pair<Coord, double> beside_edge(const Path& ring, double radius, double t,
                                     std::mt19937_64& rng) {
    const auto e = static_cast<std::size_t>(uniform_int(rng, 0, ring.size() - 2));
    const Coord a = ring[e], b = ring[e + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const double nx = (b.y - a.y) / len, ny = -(b.x - a.x) / len; // outward for CCW
    const double u = uniform(rng, 0.3, 0.7);
    const double offset = uniform(rng, 0.1, 0.5) * t + radius;
    const Coord centre{a.x + u * (b.x - a.x) + offset * nx, a.y + u * (b.y - a.y) + offset * ny};
    return {centre, std::atan2(-ny, -nx)};
}

} // namespace

std::vector<Feature> near_degenerate_polygons(int n, double scale, double t, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Feature> out;
    Path previous_star;
    for (int id = 1; id <= n; ++id) {
        Feature f;
        f.id = id;
        f.geometry.type = Geometry::Type::Polygon;
        const auto kind = uniform_int(rng, 0, 9);
        if (kind < 2) {
            f.geometry.polygons.push_back(Polygon{{sliver(scale, t, rng)}});
            out.push_back(std::move(f));
            continue;
        }
        const double radius = uniform(rng, 3.0, 20.0) * t;
        auto [centre, angle] = kind < 5 && !previous_star.empty()
            ? beside_edge(previous_star, radius, t, rng)
            : std::pair{Coord{uniform(rng, 0.0, scale), uniform(rng, 0.0, scale)},
                        uniform(rng, 0.0, two_pi)};
        Star star = random_star(centre, radius, angle, rng);
        if (uniform(rng, 0.0, 1.0) < 0.5)
            add_near_coincident(star, t, rng);
        if (uniform(rng, 0.0, 1.0) < 0.3)
            add_spike(star, radius, t, rng);
        Polygon polygon{{ring_of(star)}};
        if (uniform(rng, 0.0, 1.0) < 0.25)
            polygon.rings.push_back(hole(centre, radius, rng));
        previous_star = polygon.rings.front();
        f.geometry.polygons.push_back(std::move(polygon));
        out.push_back(std::move(f));
    }
    return out;
}

} // namespace trisnap
