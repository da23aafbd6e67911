// Paths from directed line edges (see assemble.hpp), and the output grid rounding.
#include "core/assemble.hpp"
#include "core/assemble_detail.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace trisnap {
namespace {

using detail::same_xy;

class LineAssembler {
public:
    LineAssembler(std::vector<DirectedEdge> edges, bool has_z);
    Geometry run(const std::vector<Coord>& part_starts);

private:
    std::size_t take(const Coord& v) const;
    Path trail(std::size_t k);
    void splice(Path loop);

    std::vector<DirectedEdge> m_edges;
    std::vector<bool> m_used;
    Geometry m_out;
};

LineAssembler::LineAssembler(std::vector<DirectedEdge> edges, bool has_z) : m_edges(std::move(edges))
{
    std::erase_if(m_edges, [](const DirectedEdge& e) { return same_xy(e.a, e.b); });
    std::sort(m_edges.begin(), m_edges.end(), detail::EdgeKeyLess{});
    m_used.assign(m_edges.size(), false);
    m_out.has_z = has_z;
}

// The first unused edge leaving v in edge order, or the edge count.
std::size_t LineAssembler::take(const Coord& v) const
{
    auto it = std::lower_bound(m_edges.begin(), m_edges.end(), v,
                               [](const DirectedEdge& e, const Coord& p) { return xy_less(e.a, p); });
    for (; it != m_edges.end() && same_xy(it->a, v); ++it) {
        const auto k = static_cast<std::size_t>(it - m_edges.begin());
        if (!m_used[k]) {
            return k;
        }
    }
    return m_edges.size();
}

Path LineAssembler::trail(std::size_t k)
{
    Path path{m_edges[k].a};
    for (; k < m_edges.size(); k = take(path.back())) {
        m_used[k] = true;
        path.push_back(m_edges[k].b);
    }
    return path;
}

// A closed trail that starts on a line already traced is a loop the walk stepped past (a line
// through one vertex twice): spliced in there rather than made a part of its own.
void LineAssembler::splice(Path loop)
{
    if (same_xy(loop.front(), loop.back())) {
        for (Path& line : m_out.lines) {
            const auto at = std::find_if(line.begin(), line.end(), [&](const Coord& c) { return same_xy(c, loop.front()); });
            if (at != line.end()) {
                line.insert(at + 1, loop.begin() + 1, loop.end());
                return;
            }
        }
    }
    m_out.lines.push_back(std::move(loop));
}

Geometry LineAssembler::run(const std::vector<Coord>& part_starts)
{
    std::map<std::pair<double, double>, int> balance; // edges leaving minus edges reaching
    for (const DirectedEdge& e : m_edges) {
        ++balance[{e.a.x, e.a.y}];
        --balance[{e.b.x, e.b.y}];
    }
    for (const Coord& s : part_starts) {
        if (const std::size_t k = take(s); k < m_edges.size()) {
            m_out.lines.push_back(trail(k));
        }
    }
    for (std::size_t k = 0; k < m_edges.size(); ++k) {
        if (!m_used[k] && balance[{m_edges[k].a.x, m_edges[k].a.y}] > 0) {
            m_out.lines.push_back(trail(k));
        }
    }
    for (std::size_t k = 0; k < m_edges.size(); ++k) {
        if (!m_used[k]) {
            splice(trail(k));
        }
    }
    m_out.type = m_out.lines.empty() ? Geometry::Type::Empty
               : m_out.lines.size() == 1 ? Geometry::Type::LineString : Geometry::Type::MultiLineString;
    return std::move(m_out);
}

} // namespace

Geometry assemble_lines(std::vector<DirectedEdge> edges, const std::vector<Coord>& part_starts, bool has_z)
{
    return LineAssembler(std::move(edges), has_z).run(part_starts);
}

Coord round_to_grid(Coord c, double g)
{
    if (g > 0) {
        c.x = std::round(c.x / g) * g;
        c.y = std::round(c.y / g) * g;
    }
    c.x += 0.0; // no negative zeros in the output
    c.y += 0.0;
    return c;
}

} // namespace trisnap
