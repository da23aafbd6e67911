#include "tiling/tile_job.hpp"

#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace trisnap::tiling {
namespace {

std::uint64_t point_key(double x, double y)
{
    std::uint64_t a, b;
    std::memcpy(&a, &x, 8), std::memcpy(&b, &y, 8);
    return a * 0x9E3779B97F4A7C15ull ^ (b + 0x7F4A7C15ull + (a << 6) + (a >> 2));
}

double round_to(double v, double g) { return g > 0 ? std::round(v / g) * g + 0.0 : v; }

struct Seg {
    Coord a, b;
    std::int64_t feature;
};

// Did a chain of changed edges connect the border zone of R with the core? Changed = an
// output edge that is not an input edge. Two changed edges are linked when they come within
// 2t (cells of side >= 2t, each edge in every cell its box + t covers).
bool cascade_reaches_core(const TileInput& in, const SnapResult& out, const Box& R, const Box& core, double t,
                          double grid, double& where_x, double& where_y, std::int64_t& feature)
{
    // Changed = an output edge with an end that is not an input vertex (moved or created); an
    // input edge split at an input vertex lying on it is not a change.
    std::unordered_set<std::uint64_t> input;
    auto key = [&](const Coord& p) { return point_key(round_to(p.x, grid), round_to(p.y, grid)); };
    auto add_path = [&](const Path& r) {
        for (const Coord& c : r) input.insert(key(c));
    };
    for (const Feature& f : in.features) {
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

// The box R0 grown to hold both ends of every input edge that meets it: a long edge that
// reaches into the core moves with its far end, so the tile must see what happens there.
Box reach_box(const JobContext& ctx, const Box& r0)
{
    Box r = r0;
    auto visit = [&](const Coord& p, const Coord& q) {
        if (segment_meets_box(p, q, r0)) r.add(p.x, p.y), r.add(q.x, q.y);
    };
    for (std::size_t f = 0; f < ctx.boxes.size(); ++f) {
        if (ctx.clean[f].rejected || !ctx.boxes[f].intersects(r0) || r0.contains(ctx.boxes[f])) continue;
        for (const auto& ring : ctx.clean[f].rings)
            for (std::size_t i = 0; i < ring.points.size(); ++i) visit(ring.points[i], ring.points[(i + 1) % ring.points.size()]);
        for (const auto& line : ctx.clean[f].lines)
            for (std::size_t i = 0; i + 1 < line.size(); ++i) visit(line[i], line[i + 1]);
    }
    return r;
}

} // namespace

TileOutcome run_job(const JobContext& ctx, const TileJob& job)
{
    const auto start = std::chrono::steady_clock::now();
    TileOutcome out;
    out.group = job.group;
    const double t = ctx.options.tolerance;
    SnapOptions options = ctx.options;
    options.report_region = job.report_region;
    double halo = job.halo;
    for (int attempt = 0;; ++attempt) {
        const Box R = reach_box(ctx, job.core.expanded(halo)).expanded(halo);
        std::vector<std::size_t> candidates;
        for (std::size_t f = 0; f < ctx.boxes.size(); ++f)
            if (!ctx.clean[f].rejected && ctx.boxes[f].intersects(R)) candidates.push_back(f);
        TileInput in = build_tile_input(ctx.clean, ctx.has_z, candidates, R);
        SnapResult result = snap(in.features, options);
        double x = 0, y = 0;
        std::int64_t feature = 0;
        const bool reached = ctx.max_growth > 0 && cascade_reaches_core(in, result, R, job.core, t, options.grid, x, y, feature);
        if (reached && attempt == 0) out.cascade_x = x, out.cascade_y = y, out.cascade_feature = feature;
        if (!reached || attempt >= ctx.max_growth) {
            out.cascade_unbounded = reached;
            out.halo = halo;
            out.growths = attempt;
            out.input_vertices = in.vertices;
            out.source = std::move(in.source);
            out.intact = std::move(in.intact);
            out.result = std::move(result);
            break;
        }
        halo *= 2;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

std::vector<TileOutcome> run_jobs(const JobContext& ctx, const std::vector<TileJob>& jobs, int threads,
                                  const std::function<void(const TileOutcome&)>& done)
{
    std::vector<TileOutcome> results(jobs.size());
    const int n = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::task_arena arena(n);
    arena.execute([&] {
        std::size_t next = 0;
        tbb::parallel_pipeline(
            static_cast<std::size_t>(2 * n),
            tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                                [&](tbb::flow_control& fc) -> std::size_t {
                                                    if (next >= jobs.size()) { fc.stop(); return 0; }
                                                    return next++;
                                                }) &
                tbb::make_filter<std::size_t, std::size_t>(tbb::filter_mode::parallel,
                                                           [&](std::size_t k) {
                                                               results[k] = run_job(ctx, jobs[k]);
                                                               return k;
                                                           }) &
                tbb::make_filter<std::size_t, void>(tbb::filter_mode::serial_in_order, [&](std::size_t k) {
                    if (done) done(results[k]);
                }));
    });
    return results;
}

} // namespace trisnap::tiling
