#include "tiling/tile_job.hpp"

#include "core/assemble.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace trisnap::tiling {
namespace {

// Exact point identity: both coordinates' bits (a hash table only finds them faster).
struct PointKey {
    std::uint64_t x, y;
    bool operator==(const PointKey&) const = default;
};

struct PointKeyHash {
    std::size_t operator()(const PointKey& k) const noexcept { return k.x * 0x9E3779B97F4A7C15ull ^ (k.y + (k.x << 6) + (k.x >> 2)); }
};

PointKey point_key(double x, double y) { return PointKey{std::bit_cast<std::uint64_t>(x + 0.0), std::bit_cast<std::uint64_t>(y + 0.0)}; }

struct Seg {
    Coord a, b;
    std::int64_t feature;
};

// Did a chain of changed edges connect the border zone of R with the core? Changed = an
// output edge that is not an input edge. Two changed edges are linked when they come within
// 2t (cells of side >= 2t, each edge in every cell its box + t covers).
bool cascade_reaches_core(const std::vector<Feature>& in, const SnapResult& out, const Box& R, const Box& core, double t,
                          double grid, double& where_x, double& where_y, std::int64_t& feature)
{
    // Changed = an output edge with an end that is not an input vertex (moved or created); an
    // input edge split at an input vertex lying on it is not a change.
    std::unordered_set<PointKey, PointKeyHash> input;
    auto key = [&](const Coord& p) {
        const Coord c = round_to_grid(p, grid);
        return point_key(c.x, c.y);
    };
    auto add_path = [&](const Path& r) {
        for (const Coord& c : r) input.insert(key(c));
    };
    for (const Feature& f : in) {
        for (const Polygon& p : f.geometry.polygons) std::for_each(p.rings.begin(), p.rings.end(), add_path);
        std::for_each(f.geometry.lines.begin(), f.geometry.lines.end(), add_path);
    }
    std::vector<Seg> changed;
    auto scan = [&](const Path& r, std::int64_t id) {
        for (std::size_t i = 0; i + 1 < r.size(); ++i)
            if (!input.count(key(r[i])) || !input.count(key(r[i + 1]))) changed.push_back(Seg{r[i], r[i + 1], id});
    };
    for (const FeatureOutput& f : out.features) {
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& r : p.rings) scan(r, f.id);
        for (const Path& l : f.geometry.lines) scan(l, f.id);
    }
    if (changed.empty()) return false;
    const Box inner = R.expanded(-2 * t), reach = core.expanded(2 * t);
    auto seg_box = [](const Seg& s) {
        Box b;
        b.add(s.a.x, s.a.y), b.add(s.b.x, s.b.y);
        return b;
    };
    std::vector<char> anchored(changed.size()), reaching(changed.size());
    bool any_anchor = false, any_reach = false;
    for (std::size_t k = 0; k < changed.size(); ++k) {
        const Box b = seg_box(changed[k]);
        anchored[k] = !inner.contains(b);
        reaching[k] = b.intersects(reach);
        any_anchor |= anchored[k] != 0, any_reach |= reaching[k] != 0;
        if (anchored[k] && reaching[k]) {
            where_x = changed[k].a.x, where_y = changed[k].a.y, feature = changed[k].feature;
            return true;
        }
    }
    if (!any_anchor || !any_reach) return false;
    // Union-find over cells.
    const double cell = std::max(2 * t, std::sqrt(std::max(R.width() * R.height(), 0.0) / 4e6));
    std::vector<std::size_t> parent(changed.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::unordered_map<std::uint64_t, std::size_t> first_in;
    auto visit_cell = [&](long cx, long cy, std::size_t k) {
        const std::uint64_t c = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(cx)) << 32) | static_cast<std::uint32_t>(cy);
        auto [it, added] = first_in.try_emplace(c, k);
        if (!added) parent[find(k)] = find(it->second);
    };
    for (std::size_t k = 0; k < changed.size(); ++k) {
        const Seg& s = changed[k];
        const double len = std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
        const long steps = std::max(1L, static_cast<long>(std::ceil(len / cell)));
        for (long i = 0; i <= steps; ++i) { // sample along the edge; each sample covers +- t
            const double u = static_cast<double>(i) / static_cast<double>(steps);
            const double x = s.a.x + u * (s.b.x - s.a.x), y = s.a.y + u * (s.b.y - s.a.y);
            const long x0 = static_cast<long>(std::floor((x - t - R.xmin) / cell)), x1 = static_cast<long>(std::floor((x + t - R.xmin) / cell));
            const long y0 = static_cast<long>(std::floor((y - t - R.ymin) / cell)), y1 = static_cast<long>(std::floor((y + t - R.ymin) / cell));
            for (long cx = x0; cx <= x1; ++cx)
                for (long cy = y0; cy <= y1; ++cy) visit_cell(cx, cy, k);
        }
    }
    std::unordered_map<std::size_t, int> flags;
    for (std::size_t k = 0; k < changed.size(); ++k) flags[find(k)] |= (anchored[k] ? 1 : 0) | (reaching[k] ? 2 : 0);
    for (std::size_t k = 0; k < changed.size(); ++k)
        if (reaching[k] && flags[find(k)] == 3) {
            where_x = changed[k].a.x, where_y = changed[k].a.y, feature = changed[k].feature;
            return true;
        }
    return false;
}

} // namespace

TileOutcome run_tile(const TileJob& job, const SnapOptions& base, const Gather& gather)
{
    const auto start = std::chrono::steady_clock::now();
    TileOutcome out;
    const double t = base.tolerance;
    SnapOptions options = base;
    options.report_region = job.report_region;
    double halo = job.halo;
    for (int attempt = 0;; ++attempt) {
        TileJobInput in = gather(halo);
        std::vector<Feature> features;
        std::vector<std::uint64_t> ranks;
        std::vector<bool> intact;
        features.reserve(in.features.size());
        for (TileFeature& f : in.features) {
            features.push_back(std::move(f.feature));
            ranks.push_back(f.rank);
            intact.push_back(f.intact);
        }
        in.features.clear();
        in.features.shrink_to_fit();
        // Without the cascade test nothing needs the input after the engine has cleaned it.
        SnapResult result = job.max_growth > 0 ? snap(features, options) : snap(std::move(features), options);
        double x = 0;
        double y = 0;
        std::int64_t feature = 0;
        const bool reached = job.max_growth > 0 &&
                             cascade_reaches_core(features, result, in.reach, job.core, t, options.grid, x, y, feature);
        if (reached && attempt == 0) {
            out.cascade_x = x;
            out.cascade_y = y;
            out.cascade_feature = feature;
        }
        if (!reached || attempt >= job.max_growth) {
            out.cascade_unbounded = reached;
            out.halo = halo;
            out.growths = attempt;
            out.input_vertices = in.vertices;
            out.ranks = std::move(ranks);
            out.intact = std::move(intact);
            out.result = std::move(result);
            break;
        }
        halo *= 2;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace trisnap::tiling
