#include "tiling/tile_input.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace trisnap::tiling {
namespace {

constexpr double k_two_pi = 2 * std::numbers::pi;

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// Signed angle seen from c when going from p to q, in (-pi, pi].
double sweep(const Coord& c, const Coord& p, const Coord& q)
{
    const double ax = p.x - c.x, ay = p.y - c.y, bx = q.x - c.x, by = q.y - c.y;
    return std::atan2(cross(ax, ay, bx, by), ax * bx + ay * by);
}

} // namespace

class RingCutter {
public:
    RingCutter(const Box& r, const Box& frame)
        : m_r(r), m_frame(frame), m_c{0.5 * (r.xmin + r.xmax), 0.5 * (r.ymin + r.ymax)} {}

    /// The ring (open, >= 3 points) with its runs outside R replaced; empty when it goes.
    std::vector<Coord> cut(const std::vector<Coord>& ring, bool& intact) const
    {
        const std::size_t n = ring.size();
        // The ring's box first (a cheap pass): a ring inside R keeps every edge, and one whose
        // box misses R keeps none (each edge's box lies in the ring's, so segment_meets_box's
        // first test fails for every edge), and R's centre, in R, is outside that box, so
        // outside the ring: the ring goes (locate_in_ring stays for a centre that rounding or an
        // unbounded R put elsewhere). The same answers as the edge-by-edge pass below, without
        // its predicates for the many small rings (islands) a tile's reach meets or misses whole.
        const Box rb = box_of(ring);
        if (m_r.contains(rb)) return ring;
        if (!m_r.intersects(rb)) {
            intact = false;
            if (m_c.x < rb.xmin || m_c.x > rb.xmax || m_c.y < rb.ymin || m_c.y > rb.ymax || locate_in_ring(ring, m_c) <= 0)
                return {};
            return {{rb.xmin, rb.ymin}, {rb.xmax, rb.ymin}, {rb.xmax, rb.ymax}, {rb.xmin, rb.ymax}};
        }
        std::vector<char> kept(n);
        std::size_t first = n, count = 0;
        for (std::size_t i = 0; i < n; ++i) {
            kept[i] = segment_meets_box(ring[i], ring[(i + 1) % n], m_r);
            if (kept[i]) { ++count; if (first == n) first = i; }
        }
        if (count == n) return ring;
        intact = false;
        if (count == 0) {
            if (locate_in_ring(ring, m_c) <= 0) return {};
            return {{rb.xmin, rb.ymin}, {rb.xmax, rb.ymin}, {rb.xmax, rb.ymax}, {rb.xmin, rb.ymax}};
        }
        std::vector<Coord> out;
        // Start at a kept edge; walk once round the ring.
        std::size_t i = first;
        for (std::size_t step = 0; step < n;) {
            if (kept[i]) {
                out.push_back(ring[i]);
                i = (i + 1) % n, ++step;
                continue;
            }
            const Coord& a = ring[i];
            double run = 0;
            while (!kept[i] && step < n) {
                run += sweep(m_c, ring[i], ring[(i + 1) % n]);
                i = (i + 1) % n, ++step;
            }
            out.push_back(a);
            const std::size_t from = out.size();
            detour(a, ring[i], run, out);
            for (std::size_t k = from; k < out.size(); ++k) out[k].z = a.z; // artifacts: any defined z
        }
        return out;
    }

private:
    // Points strictly between a and b (both outside R) for a path that sweeps `run` round c.
    void detour(const Coord& a, const Coord& b, double run, std::vector<Coord>& out) const
    {
        const double back = sweep(m_c, b, a);
        if (std::lround((run + back) / k_two_pi) == 0 && !segment_meets_box(a, b, m_r.expanded(1e-9 * (m_r.width() + m_r.height()))))
            return; // the straight shortcut goes round R as the run did
        const Coord pa = spoke(a), pb = spoke(b);
        const double aa = std::atan2(pa.y - m_c.y, pa.x - m_c.x), ab = std::atan2(pb.y - m_c.y, pb.x - m_c.x);
        const double phi = (ab - aa) + k_two_pi * static_cast<double>(std::lround((run - (ab - aa)) / k_two_pi));
        out.push_back(pa);
        const Coord corners[4] = {{m_frame.xmax, m_frame.ymax}, {m_frame.xmin, m_frame.ymax},
                                  {m_frame.xmin, m_frame.ymin}, {m_frame.xmax, m_frame.ymin}};
        double ang[4];
        for (int k = 0; k < 4; ++k) ang[k] = std::atan2(corners[k].y - m_c.y, corners[k].x - m_c.x);
        // Corners in angular order along the sweep, unwrapped.
        const double lo = phi > 0 ? aa : aa + phi, hi = phi > 0 ? aa + phi : aa;
        std::vector<std::pair<double, int>> hits;
        for (int k = 0; k < 4; ++k) {
            double g = ang[k] + k_two_pi * std::ceil((lo - ang[k]) / k_two_pi);
            for (; g < hi; g += k_two_pi)
                if (g > lo) hits.emplace_back(g, k);
        }
        std::sort(hits.begin(), hits.end());
        if (phi < 0) std::reverse(hits.begin(), hits.end());
        for (const auto& h : hits) out.push_back(corners[h.second]);
        out.push_back(pb);
    }

    // Where the ray from c through p leaves the frame (it never meets R beyond p).
    Coord spoke(const Coord& p) const
    {
        const double dx = p.x - m_c.x, dy = p.y - m_c.y;
        double s = std::numeric_limits<double>::infinity();
        if (dx > 0) s = std::min(s, (m_frame.xmax - m_c.x) / dx);
        if (dx < 0) s = std::min(s, (m_frame.xmin - m_c.x) / dx);
        if (dy > 0) s = std::min(s, (m_frame.ymax - m_c.y) / dy);
        if (dy < 0) s = std::min(s, (m_frame.ymin - m_c.y) / dy);
        Coord q{m_c.x + s * dx, m_c.y + s * dy};
        if (dx > 0 && q.x > m_frame.xmax) q.x = m_frame.xmax;
        if (dx < 0 && q.x < m_frame.xmin) q.x = m_frame.xmin;
        return q;
    }

    Box m_r, m_frame;
    Coord m_c;
};


bool segment_meets_box(const Coord& p, const Coord& q, const Box& b)
{
    return trisnap::segment_meets_box(p, q, b.xmin, b.ymin, b.xmax, b.ymax);
}

Box detour_frame(const Box& extent, const Box& R)
{
    Box frame = extent;
    frame.add(R);
    return frame.expanded(0.01 * (frame.width() + frame.height()) + 0.5 * (R.width() + R.height()));
}

TileCutter::TileCutter(const Box& R, const Box& frame) : m_r(R), m_cutter(std::make_unique<RingCutter>(R, frame)) {}

TileCutter::~TileCutter() = default;

void TileCutter::cut_polygon(const detail::CleanFeature& cf, Geometry& out, bool& intact) const
{
    out.type = Geometry::Type::MultiPolygon;
    for (const auto& ring : cf.rings) {
        std::vector<Coord> r = m_cutter->cut(ring.points, intact);
        if (r.empty()) {
            continue;
        }
        r.push_back(r.front());
        if (out.polygons.size() <= ring.polygon) {
            out.polygons.resize(ring.polygon + 1);
        }
        out.polygons[ring.polygon].rings.push_back(std::move(r));
    }
    std::erase_if(out.polygons, [](const Polygon& p) { return p.rings.empty(); });
}

void TileCutter::cut_lines(const detail::CleanFeature& cf, Geometry& out, bool& intact) const
{
    out.type = Geometry::Type::MultiLineString;
    for (const auto& line : cf.lines) {
        Path part;
        for (std::size_t i = 0; i + 1 < line.size(); ++i) {
            if (segment_meets_box(line[i], line[i + 1], m_r)) {
                if (part.empty()) {
                    part.push_back(line[i]);
                }
                part.push_back(line[i + 1]);
            } else {
                intact = false;
                if (!part.empty()) {
                    out.lines.push_back(std::move(part));
                    part.clear();
                }
            }
        }
        if (!part.empty()) {
            out.lines.push_back(std::move(part));
        }
    }
}

bool TileCutter::cut(const detail::CleanFeature& cf, bool has_z, Feature& out, bool& intact) const
{
    out = Feature{};
    out.id = cf.id;
    intact = true;
    if (cf.rejected) {
        return false;
    }
    if (cf.polygonal) {
        cut_polygon(cf, out.geometry, intact);
    } else {
        cut_lines(cf, out.geometry, intact);
    }
    out.geometry.has_z = has_z;
    return !out.geometry.empty();
}

std::size_t engine_vertices(const Geometry& g)
{
    std::size_t n = 0;
    for (const Polygon& p : g.polygons) {
        for (const Path& r : p.rings) {
            n += r.size() - 1;
        }
    }
    for (const Path& l : g.lines) {
        n += l.size();
    }
    return n;
}

TileInput build_tile_input(const std::vector<detail::CleanFeature>& clean, const std::vector<bool>& has_z,
                           const std::vector<std::size_t>& candidates, const Box& R)
{
    TileInput in;
    // The frame holds every vertex of the candidates (as the layer's extent does in a run).
    Box extent;
    for (std::size_t f : candidates) {
        for (const auto& ring : clean[f].rings) {
            for (const Coord& c : ring.points) {
                extent.add(c.x, c.y);
            }
        }
        for (const auto& line : clean[f].lines) {
            for (const Coord& c : line) {
                extent.add(c.x, c.y);
            }
        }
    }
    const TileCutter cutter(R, detour_frame(extent, R));
    for (std::size_t f : candidates) {
        Feature out;
        bool intact = true;
        if (!cutter.cut(clean[f], has_z[f], out, intact)) {
            continue;
        }
        in.vertices += engine_vertices(out.geometry);
        in.features.push_back(std::move(out));
        in.source.push_back(f);
        in.intact.push_back(intact);
    }
    return in;
}

} // namespace trisnap::tiling
