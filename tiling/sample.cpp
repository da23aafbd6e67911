#include "tiling/sample.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace trisnap::tiling {
namespace {

// splitmix64's finaliser: every input bit reaches every output bit.
std::uint64_t mix(std::uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

} // namespace

bool VertexSample::kept(double x, double y) const
{
    if (m_level == 0) {
        return true;
    }
    // +0.0 so that -0 and 0 (the same point) hash alike.
    const std::uint64_t h = mix(std::bit_cast<std::uint64_t>(x + 0.0) ^ mix(std::bit_cast<std::uint64_t>(y + 0.0)));
    return (h >> (64 - m_level)) == 0;
}

void VertexSample::add(double x, double y)
{
    if (!std::isfinite(x) || !std::isfinite(y)) {
        return;
    }
    m_extent.add(x, y);
    ++m_vertices;
    if (!kept(x, y)) {
        return;
    }
    if (m_xs.size() == m_xs.capacity()) {
        // Doubled, but never past the cap (and the one vertex over it that raises the level):
        // the sample holds at most its 16 bytes a vertex, not twice that after a doubling.
        const std::size_t room = std::min(std::max<std::size_t>(2 * m_xs.capacity(), 1024), m_cap + 1);
        m_xs.reserve(std::max(room, m_xs.size() + 1));
        m_ys.reserve(std::max(room, m_ys.size() + 1));
    }
    m_xs.push_back(x);
    m_ys.push_back(y);
    while (m_xs.size() > m_cap && m_level < 63) {
        ++m_level;
        keep_kept(m_xs, m_ys);
    }
}

void VertexSample::keep_kept(std::vector<double>& xs, std::vector<double>& ys) const
{
    std::size_t k = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        if (kept(xs[i], ys[i])) {
            xs[k] = xs[i];
            ys[k] = ys[i];
            ++k;
        }
    }
    xs.resize(k);
    ys.resize(k);
}

// Each side's vertices are already those kept at its own level. The level is raised (both
// sides filtered) until the two together fit the cap, before they are put together: the same
// level and vertices as filtering after (a level keeps a subset of the level below), without
// holding up to twice the cap on the way. Then the later ones are copied after these.
void VertexSample::append(VertexSample&& later)
{
    m_extent.add(later.m_extent);
    m_vertices += later.m_vertices;
    int level = std::max(m_level, later.m_level);
    for (;;) {
        if (m_level < level) {
            m_level = level;
            keep_kept(m_xs, m_ys);
        }
        if (later.m_level < level) {
            later.m_level = level;
            later.keep_kept(later.m_xs, later.m_ys);
        }
        if (m_xs.size() + later.m_xs.size() <= m_cap || level >= 63) {
            break;
        }
        ++level;
    }
    m_xs.reserve(m_xs.size() + later.m_xs.size());
    m_ys.reserve(m_ys.size() + later.m_ys.size());
    m_xs.insert(m_xs.end(), later.m_xs.begin(), later.m_xs.end());
    m_ys.insert(m_ys.end(), later.m_ys.begin(), later.m_ys.end());
    later = VertexSample(later.m_cap);
}

PlanInput VertexSample::take()
{
    PlanInput in;
    in.extent = m_extent;
    in.vertices = m_vertices;
    in.xs = std::move(m_xs);
    in.ys = std::move(m_ys);
    in.level = m_level;
    return in;
}

} // namespace trisnap::tiling
