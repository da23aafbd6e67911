#include "core/shared_boundaries.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace trisnap::detail {
namespace {

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; }

// The length of the part of p-q inside the half-open box b: clipped to the closed box, less a
// piece lying on b's upper or right side (those points belong to the next box), so the tiles'
// lengths of one segment add up to its length (to rounding), none counted twice.
double clipped_length(const Coord& p, const Coord& q, const Region& b)
{
    if ((p.y == q.y && !(b.ymin <= p.y && p.y < b.ymax)) || (p.x == q.x && !(b.xmin <= p.x && p.x < b.xmax))) {
        return 0.0;
    }
    double t0 = 0.0;
    double t1 = 1.0;
    const double d[2] = {q.x - p.x, q.y - p.y};
    const double lo[2] = {b.xmin - p.x, b.ymin - p.y};
    const double hi[2] = {b.xmax - p.x, b.ymax - p.y};
    for (int k = 0; k < 2; ++k) {
        if (d[k] == 0.0) {
            if (lo[k] > 0.0 || hi[k] < 0.0) {
                return 0.0;
            }
            continue;
        }
        double a = lo[k] / d[k];
        double c = hi[k] / d[k];
        if (a > c) {
            std::swap(a, c);
        }
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
    }
    return t1 > t0 ? (t1 - t0) * std::hypot(d[0], d[1]) : 0.0;
}

Region intersection(const Region& a, const Region& b)
{
    return Region{std::max(a.xmin, b.xmin), std::max(a.ymin, b.ymin), std::min(a.xmax, b.xmax), std::min(a.ymax, b.ymax)};
}

// The polygon features bounding an edge (owning it an odd number of times), ascending; empty
// when there are more than k_max_stacked.
void bounding(const Mesh& mesh, std::span<const OwnerRef> refs, std::vector<FeatureCount>& counts,
              std::vector<std::uint32_t>& out)
{
    out.clear();
    mesh.polygon_ownership(refs, counts);
    for (const FeatureCount& c : counts) {
        if (c.times % 2 == 1) {
            out.push_back(c.feature);
        }
    }
    if (out.size() > k_max_stacked) {
        out.clear();
    }
}

} // namespace

SharedBoundaryEvidence::SharedBoundaryEvidence(const Region& region, const std::vector<Region>& cores, const Region& extent)
    : m_cores(cores.empty() ? std::vector<Region>{region} : cores), m_extent(extent)
{
}

void SharedBoundaryEvidence::before(const Mesh& mesh)
{
    std::vector<Region> boxes;
    for (const Region& core : m_cores) {
        const Region box = intersection(core, m_extent);
        if (box.xmin <= box.xmax && box.ymin <= box.ymax) {
            boxes.push_back(box);
        }
    }
    if (boxes.empty()) {
        return;
    }
    std::vector<FeatureCount> counts;
    std::vector<std::uint32_t> features;
    mesh.for_each_edge_with_owners([&](std::uint32_t u, std::uint32_t v, std::span<const OwnerRef> refs) {
        if (refs.size() < 2) {
            return;
        }
        bounding(mesh, refs, counts, features);
        if (features.size() < 2) {
            return;
        }
        const Xy a = mesh.xy(u);
        const Xy b = mesh.xy(v);
        const Coord p{a.x, a.y};
        const Coord q{b.x, b.y};
        if (std::none_of(boxes.begin(), boxes.end(), [&](const Region& box) {
                return segment_meets_box(p, q, box.xmin, box.ymin, box.xmax, box.ymax);
            })) {
            return;
        }
        double length = 0.0;
        for (const Region& core : m_cores) {
            length += clipped_length(p, q, core);
        }
        const Coord low = xy_less(p, q) ? p : q;
        for (std::size_t i = 0; i < features.size(); ++i) {
            for (std::size_t j = i + 1; j < features.size(); ++j) {
                auto [it, added] = m_pairs.try_emplace(pair_key(features[i], features[j]));
                if (added || !it->second.before || xy_less(low, it->second.at)) {
                    it->second.at = low;
                }
                it->second.before = true;
                it->second.length += length;
            }
        }
    });
}

void SharedBoundaryEvidence::after(const Mesh& mesh)
{
    std::vector<FeatureCount> counts;
    std::vector<std::uint32_t> features;
    mesh.for_each_edge_with_owners([&](std::uint32_t u, std::uint32_t v, std::span<const OwnerRef> refs) {
        if (refs.size() < 2) {
            return; // bounds one polygon at most
        }
        if (!mesh.alive(u) || !mesh.alive(v)) {
            return;
        }
        const Xy a = mesh.xy(u);
        const Xy b = mesh.xy(v);
        const double mx = 0.5 * (a.x + b.x);
        const double my = 0.5 * (a.y + b.y);
        if (!m_extent.contains_closed(mx, my) ||
            std::none_of(m_cores.begin(), m_cores.end(), [&](const Region& c) { return c.contains(mx, my); })) {
            return;
        }
        bounding(mesh, refs, counts, features);
        if (features.size() < 2 || !mesh.is_triangulation_constraint(u, v)) {
            return;
        }
        for (std::size_t i = 0; i < features.size(); ++i) {
            for (std::size_t j = i + 1; j < features.size(); ++j) {
                m_pairs[pair_key(features[i], features[j])].after = true;
            }
        }
    });
}

std::vector<std::vector<SharedBoundary>> SharedBoundaryEvidence::by_feature(const std::vector<Outline>& clean) const
{
    std::vector<std::vector<SharedBoundary>> out(clean.size());
    for (const auto& [key, pair] : m_pairs) {
        const auto a = static_cast<std::uint32_t>(key >> 32);
        const auto b = static_cast<std::uint32_t>(key & 0xffffffffU);
        SharedBoundary s;
        s.before = pair.before;
        s.after = pair.after;
        s.length = pair.length;
        s.x = pair.before ? pair.at.x : 0.0;
        s.y = pair.before ? pair.at.y : 0.0;
        s.other = clean[b].id;
        s.other_position = clean[b].index;
        out[a].push_back(s);
        s.other = clean[a].id;
        s.other_position = clean[a].index;
        out[b].push_back(s);
    }
    for (auto& list : out) {
        std::sort(list.begin(), list.end(), [](const SharedBoundary& l, const SharedBoundary& r) { return l.other < r.other; });
    }
    return out;
}

void merge_shared_boundaries(std::vector<SharedBoundary>& shared)
{
    std::stable_sort(shared.begin(), shared.end(), [](const SharedBoundary& l, const SharedBoundary& r) { return l.other < r.other; });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < shared.size(); ++k) {
        const SharedBoundary& s = shared[k];
        if (kept == 0 || shared[kept - 1].other != s.other) {
            shared[kept++] = s;
            continue;
        }
        SharedBoundary& m = shared[kept - 1];
        if (s.before && (!m.before || std::tie(s.x, s.y) < std::tie(m.x, m.y))) {
            m.x = s.x;
            m.y = s.y;
        }
        m.length += s.length;
        m.before = m.before || s.before;
        m.after = m.after || s.after;
    }
    shared.resize(kept);
}

bool lost_candidate(const SharedBoundary& s, double tolerance)
{
    return s.before && !s.after && s.length >= tolerance;
}

bool report_lost_boundaries(std::int64_t id, std::uint64_t position, bool written, double tolerance,
                            const std::vector<SharedBoundary>& shared,
                            const std::function<bool(const SharedBoundary&)>& other_written,
                            const std::function<std::string(std::int64_t)>& name, std::vector<Problem>& problems)
{
    if (!written) {
        return false;
    }
    constexpr std::size_t named = 5;
    std::size_t lost = 0;
    std::string others;
    Coord at{};
    for (const SharedBoundary& s : shared) {
        if (s.other_position >= position || !lost_candidate(s, tolerance) || !other_written(s)) {
            continue;
        }
        if (lost == 0 || std::tie(s.x, s.y) < std::tie(at.x, at.y)) {
            at = Coord{s.x, s.y};
        }
        if (lost < named) {
            others += (lost == 0 ? "" : ", ") + name(s.other);
        }
        ++lost;
    }
    if (lost == 0) {
        return false;
    }
    if (lost > named) {
        others += " and " + std::to_string(lost - named) + " more";
    }
    problems.push_back(Problem{id, ProblemCode::shared_boundary_lost,
        "no longer shares a boundary with " + others +
            ": the boundary they shared collapsed (its vertices, closer than the tolerance, merged); both are written",
        at.x, at.y});
    return true;
}

} // namespace trisnap::detail
