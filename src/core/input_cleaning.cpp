#include "core/input_cleaning.hpp"

#include "core/snap.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace trisnap::detail {
namespace {

// A coordinate c carries about |c| * 2^-52 of rounding; below ~2^8 ulps the tolerance cannot be
// told apart from rounding noise, and the triangulation's exact predicates would see near-random
// geometry. Such features are rejected with problem 109 rather than snapped unpredictably.
// Beyond k_max_coordinate squared coordinate differences would overflow, whatever the tolerance.
bool too_large(double c, double tolerance)
{
    return std::abs(c) * 0x1p-44 > tolerance || std::abs(c) > k_max_coordinate;
}

struct Flags {
    bool unclosed = false, repeated = false, degenerate_ring = false, degenerate_line = false;
    bool non_finite = false, huge = false;
    Coord where{std::nan(""), std::nan("")};
};

void scan_coords(const Path& path, double tolerance, Flags& flags)
{
    for (const Coord& c : path) {
        if (!std::isfinite(c.x) || !std::isfinite(c.y)) {
            flags.non_finite = true;
        } else if (too_large(c.x, tolerance) || too_large(c.y, tolerance)) {
            flags.huge = true;
            flags.where = c;
        } else if (std::isnan(flags.where.x)) {
            flags.where = c;
        }
    }
}

std::vector<Coord> drop_repeats(const Path& path, Flags& flags)
{
    std::vector<Coord> out;
    out.reserve(path.size());
    for (const Coord& c : path) {
        if (!out.empty() && out.back() == c) {
            flags.repeated = true;
            continue;
        }
        out.push_back(c);
    }
    return out;
}

std::size_t distinct_points(std::vector<Coord> pts)
{
    std::sort(pts.begin(), pts.end(), [](const Coord& a, const Coord& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    return static_cast<std::size_t>(std::unique(pts.begin(), pts.end()) - pts.begin());
}

// Returns the open ring (no closing point), empty when fewer than 3 distinct points remain.
std::vector<Coord> clean_ring(const Path& ring, Flags& flags)
{
    std::vector<Coord> pts = drop_repeats(ring, flags);
    if (pts.size() >= 2 && pts.front() == pts.back()) {
        pts.pop_back();
    } else if (!pts.empty()) {
        flags.unclosed = true;
    }
    if (distinct_points(pts) < 3) { // also a ring going back and forth between two points
        flags.degenerate_ring = true;
        pts.clear();
    }
    return pts;
}

void clean_polygons(const Geometry& g, CleanFeature& out, Flags& flags)
{
    for (const Polygon& poly : g.polygons) {
        const auto part = static_cast<std::uint32_t>(out.shells);
        for (std::size_t r = 0; r < poly.rings.size(); ++r) {
            std::vector<Coord> pts = clean_ring(poly.rings[r], flags);
            if (pts.empty()) {
                if (r == 0) break; // no shell: the holes have nothing to be holes of
                continue;
            }
            out.rings.push_back(CleanRing{std::move(pts), part, r != 0});
            (r == 0 ? out.shells : out.holes) += 1;
        }
    }
}

void clean_lines(const Geometry& g, CleanFeature& out, Flags& flags)
{
    for (const Path& line : g.lines) {
        std::vector<Coord> pts = drop_repeats(line, flags);
        if (pts.size() < 2) {
            flags.degenerate_line = true;
            continue;
        }
        out.lines.push_back(std::move(pts));
    }
}

void report(const CleanFeature& f, const Flags& flags, std::vector<Problem>& problems)
{
    auto add = [&](ProblemCode code, std::string message) {
        problems.push_back(Problem{f.id, code, std::move(message), flags.where.x, flags.where.y});
    };
    if (flags.non_finite) add(ProblemCode::non_finite_coordinate, "NaN or infinite coordinate; feature rejected");
    if (flags.huge) add(ProblemCode::huge_coordinate, "coordinate too large for the tolerance at double precision; feature rejected");
    if (flags.non_finite || flags.huge) return;
    if (flags.unclosed) add(ProblemCode::unclosed_ring, "unclosed ring was closed");
    if (flags.repeated) add(ProblemCode::repeated_points, "consecutive duplicate points were removed");
    if (flags.degenerate_ring) add(ProblemCode::degenerate_ring, "ring with fewer than 3 distinct points was dropped");
    if (flags.degenerate_line) add(ProblemCode::degenerate_line, "line with fewer than 2 distinct points was dropped");
}


} // namespace

CleanFeature clean_feature(std::int64_t id, const Geometry& g, std::size_t index, double tolerance,
                           std::vector<Problem>& problems)
{
    CleanFeature out;
    out.index = index;
    out.id = id;
    out.polygonal = g.is_polygonal();
    if (!g.is_polygonal() && !g.is_lineal()) {
        out.rejected = true;
        const bool empty = g.type == Geometry::Type::Empty;
        problems.push_back(Problem{id, empty ? ProblemCode::empty_geometry : ProblemCode::unsupported_geometry,
                                   empty ? "empty geometry" : "geometry type is not snapped",
                                   std::nan(""), std::nan("")});
        return out;
    }
    Flags flags;
    for (const Polygon& p : g.polygons) for (const Path& r : p.rings) scan_coords(r, tolerance, flags);
    for (const Path& l : g.lines) scan_coords(l, tolerance, flags);
    if (!flags.non_finite && !flags.huge) {
        if (out.polygonal) clean_polygons(g, out, flags);
        else clean_lines(g, out, flags);
    }
    report(out, flags, problems);
    out.rejected = flags.non_finite || flags.huge;
    if (!out.rejected && out.rings.empty() && out.lines.empty()) {
        out.rejected = true;
        problems.push_back(Problem{id, ProblemCode::empty_geometry,
                                   "nothing usable remains after cleaning", flags.where.x, flags.where.y});
    }
    return out;
}

std::vector<CleanFeature> clean_input(const std::vector<Feature>& features, double tolerance,
                                      std::vector<Problem>& problems)
{
    std::vector<CleanFeature> out;
    out.reserve(features.size());
    for (std::size_t i = 0; i < features.size(); ++i)
        out.push_back(clean_feature(features[i].id, features[i].geometry, i, tolerance, problems));
    return out;
}

namespace {

std::uint32_t count32(std::size_t n, const char* what)
{
    if (n > std::numeric_limits<std::uint32_t>::max()) {
        throw std::length_error(std::string("more than 2^32 ") + what);
    }
    return static_cast<std::uint32_t>(n);
}

} // namespace

// Each field is set by name; a field added to CleanFeature must be looked at here too.
static_assert(sizeof(CleanFeature) == 88, "CleanFeature changed: see whether its outline needs the new field");

Outline outline_of(const CleanFeature& f)
{
    Outline o;
    o.index = f.index;
    o.id = f.id;
    o.polygonal = f.polygonal;
    o.rejected = f.rejected;
    assert(f.polygonal ? f.lines.empty() : f.rings.empty()); // clean_feature makes rings or lines
    o.paths = count32(f.rings.size() + f.lines.size(), "rings or lines in one feature");
    o.parts = count32(f.polygonal ? f.shells : f.lines.size(), "parts in one feature");
    o.holes = count32(f.holes, "holes in one feature");
    const Coord* first = nullptr;
    if (f.polygonal && !f.rings.empty() && !f.rings.front().points.empty()) first = &f.rings.front().points.front();
    if (!f.polygonal && !f.lines.empty() && !f.lines.front().empty()) first = &f.lines.front().front();
    if (first != nullptr) {
        o.x = first->x;
        o.y = first->y;
    }
    return o;
}

Outlines make_outlines(const std::vector<CleanFeature>& features)
{
    Outlines out;
    out.features.reserve(features.size());
    std::size_t lines = 0;
    for (const CleanFeature& f : features) lines += f.lines.size();
    out.line_starts.reserve(lines);
    for (const CleanFeature& f : features) {
        Outline& o = out.features.emplace_back(outline_of(f));
        o.first_line = count32(out.line_starts.size(), "lines in one run");
        for (const std::vector<Coord>& l : f.lines) out.line_starts.push_back(l.front());
    }
    return out;
}

} // namespace trisnap::detail
