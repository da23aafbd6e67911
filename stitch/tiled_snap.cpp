#include "stitch/tiled_snap.hpp"

#include "core/input_cleaning.hpp"
#include "core/outcome.hpp"
#include "core/assemble.hpp"
#include "stitch/edges.hpp"
#include "tiling/tile_job.hpp"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

namespace trisnap::stitch {
namespace {

using tiling::Box;
using tiling::TileOutcome;

double seconds_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Box box_of_clean(const detail::CleanFeature& cf)
{
    Box b;
    for (const auto& r : cf.rings)
        for (const Coord& c : r.points) b.add(c.x, c.y);
    for (const auto& l : cf.lines)
        for (const Coord& c : l) b.add(c.x, c.y);
    return b;
}

struct Groups {
    std::vector<std::size_t> of_leaf;              ///< group id per plan leaf
    std::vector<std::vector<std::size_t>> leaves;  ///< leaves per group id (empty: merged away)
};

class Stitcher {
public:
    Stitcher(const std::vector<Feature>& features, const SnapOptions& options, const TilingOptions& tiling)
        : m_features(features), m_options(options), m_tiling(tiling) {}

    TiledResult run(const TileProgress& progress);

private:
    std::size_t owner_group(double x, double y) const { return m_groups.of_leaf[m_plan.leaf_of(x, y)]; }
    bool in_extent(double x, double y) const
    {
        const Box& e = m_plan.extent();
        return e.xmin <= x && x <= e.xmax && e.ymin <= y && y <= e.ymax;
    }
    tiling::TileJob job_for(std::size_t group) const;
    /// Groups within 2t of the edge, when there are several (else empty).
    void seam_groups(const Edge& e, std::vector<std::size_t>& groups) const;
    std::vector<std::pair<std::size_t, std::size_t>> check_seams();
    void merge(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, std::vector<std::size_t>& pending);
    void assemble(TiledResult& out);

    const std::vector<Feature>& m_features;
    const SnapOptions& m_options;
    const TilingOptions& m_tiling;
    std::vector<detail::CleanFeature> m_clean;
    std::vector<bool> m_has_z;
    std::vector<Box> m_boxes;
    tiling::TilePlan m_plan;
    Groups m_groups;
    std::map<std::size_t, TileOutcome> m_outcomes; ///< by group id
    std::map<std::size_t, std::size_t> m_runs;     ///< runs per leaf set (by group's first leaf)
    std::map<std::size_t, double> m_merged_halo;   ///< a merged tile starts from the widest halo its parts had
    std::vector<Problem> m_problems;
    StitchStats m_stats;
    double m_seam = 0; ///< band width around seams
};

tiling::TileJob Stitcher::job_for(std::size_t group) const
{
    tiling::TileJob job;
    job.group = group;
    Region region{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (std::size_t leaf : m_groups.leaves[group]) {
        const Region& r = m_plan.core(leaf);
        job.core.add(tiling::clip(r, m_plan.extent()));
        region.xmin = std::min(region.xmin, r.xmin), region.ymin = std::min(region.ymin, r.ymin);
        region.xmax = std::max(region.xmax, r.xmax), region.ymax = std::max(region.ymax, r.ymax);
    }
    job.report_region = region;
    job.halo = m_tiling.halo_factor * m_options.tolerance;
    if (auto it = m_merged_halo.find(group); it != m_merged_halo.end()) job.halo = std::max(job.halo, it->second);
    return job;
}

void Stitcher::seam_groups(const Edge& e, std::vector<std::size_t>& groups) const
{
    groups.clear();
    Box b;
    b.add(e.a.x, e.a.y), b.add(e.b.x, e.b.y);
    std::vector<std::size_t> leaves;
    m_plan.query(b.expanded(m_seam), leaves);
    for (std::size_t leaf : leaves) groups.push_back(m_groups.of_leaf[leaf]);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    if (groups.size() < 2) groups.clear();
}

// Per group: X = edges it produced near a seam with another group, Y = edges the stitched
// layer holds there. Any difference names the pair of groups to merge.
std::vector<std::pair<std::size_t, std::size_t>> Stitcher::check_seams()
{
    std::map<std::size_t, std::vector<Edge>> produced, stitched;
    // Per tile in parallel: its edges near a seam, and those it owns with the tiles they face.
    struct Near {
        std::vector<Edge> produced;
        std::vector<std::pair<Edge, std::vector<std::size_t>>> owned;
    };
    std::vector<std::pair<std::size_t, const TileOutcome*>> list;
    for (auto& [g, oc] : m_outcomes) list.emplace_back(g, &oc);
    std::vector<Near> near(list.size());
    const int threads = m_tiling.threads > 0 ? m_tiling.threads : tbb::info::default_concurrency();
    tbb::task_arena(threads).execute([&] {
        tbb::parallel_for(std::size_t{0}, list.size(), [&](std::size_t i) {
            const auto [g, oc] = list[i];
            std::vector<Edge> edges;
            std::vector<std::size_t> groups;
            for (std::size_t k = 0; k < oc->result.features.size(); ++k) {
                edges.clear();
                edges_of(oc->result.features[k].geometry, static_cast<std::uint32_t>(oc->source[k]), edges);
                for (const Edge& e : edges) {
                    seam_groups(e, groups);
                    if (groups.empty() || !std::binary_search(groups.begin(), groups.end(), g)) continue;
                    near[i].produced.push_back(e);
                    if (in_extent(e.mx(), e.my()) && owner_group(e.mx(), e.my()) == g) near[i].owned.emplace_back(e, groups);
                }
            }
        });
    });
    for (std::size_t i = 0; i < list.size(); ++i) {
        produced[list[i].first] = std::move(near[i].produced);
        for (const auto& [e, groups] : near[i].owned)
            for (std::size_t h : groups) stitched[h].push_back(e);
    }
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    for (auto& [g, oc] : m_outcomes) {
        std::vector<Edge>& x = produced[g];
        std::vector<Edge>& y = stitched[g];
        std::sort(x.begin(), x.end()), std::sort(y.begin(), y.end());
        if (x == y) continue;
        std::vector<Edge> only_x, only_y;
        std::set_difference(x.begin(), x.end(), y.begin(), y.end(), std::back_inserter(only_x));
        std::set_difference(y.begin(), y.end(), x.begin(), x.end(), std::back_inserter(only_y));
        std::size_t before = pairs.size();
        const Edge* first = nullptr;
        for (const Edge& e : only_x)
            if (in_extent(e.mx(), e.my()))
                if (std::size_t o = owner_group(e.mx(), e.my()); o != g) pairs.emplace(std::min(o, g), std::max(o, g)), first = first ? first : &e;
        for (const Edge& e : only_y)
            if (std::size_t o = owner_group(e.mx(), e.my()); o != g) pairs.emplace(std::min(o, g), std::max(o, g)), first = first ? first : &e;
        if (pairs.size() > before && first)
            m_problems.push_back(Problem{m_clean[first->feature].id, ProblemCode::seam_mismatch,
                "tiles disagreed along a seam (" + std::to_string(only_x.size() + only_y.size()) +
                " edges); they were merged and snapped again", first->mx(), first->my()});
    }
    return {pairs.begin(), pairs.end()};
}

void Stitcher::merge(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, std::vector<std::size_t>& pending)
{
    std::map<std::size_t, std::size_t> parent;
    auto find = [&](std::size_t x) {
        while (parent.count(x) && parent[x] != x) x = parent[x];
        return x;
    };
    for (auto [a, b] : pairs) {
        const std::size_t ra = find(a), rb = find(b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb), parent.try_emplace(std::min(ra, rb), std::min(ra, rb));
    }
    std::map<std::size_t, std::vector<std::size_t>> merged; // root -> old groups
    for (auto& [g, p] : parent) merged[find(g)].push_back(g);
    pending.clear();
    for (auto& [root, olds] : merged) {
        const std::size_t id = m_groups.leaves.size();
        std::vector<std::size_t> leaves;
        double halo = 0;
        for (std::size_t g : olds) {
            leaves.insert(leaves.end(), m_groups.leaves[g].begin(), m_groups.leaves[g].end());
            m_groups.leaves[g].clear();
            if (auto it = m_outcomes.find(g); it != m_outcomes.end()) halo = std::max(halo, it->second.halo), m_outcomes.erase(it);
        }
        std::sort(leaves.begin(), leaves.end());
        for (std::size_t leaf : leaves) m_groups.of_leaf[leaf] = id;
        m_groups.leaves.push_back(std::move(leaves));
        pending.push_back(id);
        m_stats.seam_merges += olds.size() - 1;
        m_merged_halo[id] = halo;
    }
}

void Stitcher::assemble(TiledResult& out)
{
    SnapResult& res = out.result;
    const std::size_t n = m_clean.size();
    std::vector<std::vector<Edge>> owned(n);
    std::vector<std::vector<std::size_t>> contributors(n);
    std::vector<const FeatureOutput*> whole(n, nullptr);
    std::vector<double> moved(n, 0.0);
    std::vector<Edge> edges;
    std::map<std::pair<std::int64_t, int>, Problem> located; // (feature id, code) -> smallest place
    for (auto& [g, oc] : m_outcomes) {
        TileReport rep;
        rep.id = m_groups.leaves[g].front();
        rep.leaves = m_groups.leaves[g].size();
        rep.halo = oc.halo;
        rep.growths = oc.growths;
        rep.features = oc.source.size();
        rep.input_vertices = oc.input_vertices;
        rep.seconds = oc.seconds;
        rep.runs = m_runs[rep.id];
        for (std::size_t leaf : m_groups.leaves[g]) rep.core.add(tiling::clip(m_plan.core(leaf), m_plan.extent()));
        res.stats += oc.result.stats;
        for (std::size_t k = 0; k < oc.result.features.size(); ++k) {
            const std::size_t f = oc.source[k];
            const FeatureOutput& fo = oc.result.features[k];
            moved[f] = std::max(moved[f], fo.max_displacement);
            edges.clear();
            edges_of(fo.geometry, static_cast<std::uint32_t>(f), edges);
            std::size_t mine = 0;
            for (const Edge& e : edges)
                if (in_extent(e.mx(), e.my()) && owner_group(e.mx(), e.my()) == g) owned[f].push_back(e), ++mine;
            rep.output_edges_owned += mine;
            if (mine > 0) contributors[f].push_back(g);
            if (mine > 0 && mine == edges.size() && oc.intact[k]) whole[f] = &fo;
        }
        for (const Problem& p : oc.result.problems) {
            const int code = static_cast<int>(p.code);
            if (code != 105 && code != 205 && code != 207 && code != 209) continue; // the rest is recomputed
            if (code != 105 && owner_group(p.x, p.y) != g) continue;
            ++rep.problems;
            auto [it, added] = located.try_emplace({p.feature_id, code}, p);
            if (!added && std::tie(p.x, p.y) < std::tie(it->second.x, it->second.y)) it->second = p;
        }
        out.tiles.push_back(rep);
    }
    // Per-input counts are global, not sums over tiles.
    res.stats.input_features = m_features.size();
    res.stats.input_vertices = m_plan.input_vertices();
    res.stats.collapsed_features = 0;
    res.stats.max_displacement = 0;
    res.stats.output_vertices = 0;
    std::map<std::int64_t, std::size_t> index_of_id;
    for (std::size_t f = 0; f < n; ++f) index_of_id.emplace(m_clean[f].id, f);
    for (auto& [key, p] : located) {
        if (p.code == ProblemCode::self_intersection) { // placed where the engine places it
            const detail::CleanFeature& cf = m_clean[index_of_id.at(p.feature_id)];
            if (!cf.rings.empty()) p.x = cf.rings[0].points[0].x, p.y = cf.rings[0].points[0].y;
        }
        m_problems.push_back(p);
    }
    // Features cut by seams are rebuilt in parallel (each on its own; the order of work
    // changes nothing), the rest is copied.
    std::vector<std::size_t> cut;
    for (std::size_t f = 0; f < n; ++f)
        if (!m_clean[f].rejected && !(contributors[f].size() == 1 && whole[f]) && !owned[f].empty()) cut.push_back(f);
    std::vector<Geometry> rebuilt(cut.size());
    const int threads = m_tiling.threads > 0 ? m_tiling.threads : tbb::info::default_concurrency();
    tbb::task_arena(threads).execute([&] {
        tbb::parallel_for(std::size_t{0}, cut.size(), [&](std::size_t k) {
            const std::size_t f = cut[k];
            const detail::CleanFeature& cf = m_clean[f];
            const bool has_z = m_features[cf.index].geometry.has_z;
            std::vector<DirectedEdge> edges;
            edges.reserve(owned[f].size());
            for (const Edge& e : owned[f]) {
                edges.push_back(DirectedEdge{e.a, e.b});
            }
            if (cf.polygonal) {
                rebuilt[k] = assemble_polygons(std::move(edges), has_z);
            } else {
                std::vector<Coord> starts;
                for (const auto& line : cf.lines) {
                    starts.push_back(round_to_grid(line.front(), m_options.grid));
                }
                rebuilt[k] = assemble_lines(std::move(edges), starts, has_z);
            }
        });
    });
    std::size_t next_cut = 0;
    for (std::size_t f = 0; f < n; ++f) {
        const detail::CleanFeature& cf = m_clean[f];
        FeatureOutput& fo = res.features[cf.index];
        fo.id = cf.id;
        if (cf.rejected) continue;
        const bool has_z = m_features[cf.index].geometry.has_z;
        if (next_cut < cut.size() && cut[next_cut] == f) {
            fo.geometry = std::move(rebuilt[next_cut++]);
            ++m_stats.assembled_features;
        } else if (contributors[f].size() == 1 && whole[f]) {
            fo.geometry = whole[f]->geometry;
            ++m_stats.copied_features;
        }
        fo.geometry.has_z = has_z;
        fo.max_displacement = moved[f];
        res.stats.max_displacement = std::max(res.stats.max_displacement, moved[f]);
        for (const Polygon& p : fo.geometry.polygons)
            for (const Path& r : p.rings) res.stats.output_vertices += r.size() - 1;
        for (const Path& l : fo.geometry.lines) res.stats.output_vertices += l.size();
        if (detail::outcome_problems(cf, fo.geometry, moved[f], m_options, m_problems)) ++res.stats.collapsed_features;
    }
}

TiledResult Stitcher::run(const TileProgress& progress)
{
    TiledResult out;
    SnapResult& res = out.result;
    res.features.resize(m_features.size());
    for (std::size_t i = 0; i < m_features.size(); ++i) {
        res.features[i].id = m_features[i].id;
        res.features[i].geometry.has_z = m_features[i].geometry.has_z;
    }
    m_clean = detail::clean_input(m_features, m_options.tolerance, m_problems);
    for (const detail::CleanFeature& cf : m_clean) {
        m_has_z.push_back(m_features[cf.index].geometry.has_z);
        m_boxes.push_back(box_of_clean(cf));
    }
    m_plan = tiling::make_plan(m_features, m_tiling.plan);
    m_seam = 2 * m_options.tolerance + 4 * m_options.grid;
    m_stats.leaves = m_plan.size();
    m_groups.of_leaf.resize(m_plan.size());
    std::vector<std::size_t> pending;
    for (std::size_t leaf = 0; leaf < m_plan.size(); ++leaf) {
        m_groups.of_leaf[leaf] = leaf;
        m_groups.leaves.push_back({leaf});
        // Leaves without data (grid cells off the extent) run nothing.
        if (!tiling::clip(m_plan.core(leaf), m_plan.extent()).empty()) pending.push_back(leaf);
    }
    const tiling::JobContext ctx{m_clean, m_has_z, m_boxes, m_options, m_tiling.max_growth};
    for (;;) {
        // The biggest tiles start first, so the last ones to finish are small (the order of
        // jobs changes nothing in the output).
        std::vector<std::pair<std::size_t, std::size_t>> order; // (-size, group)
        for (std::size_t g : pending) {
            std::size_t n = 0;
            for (std::size_t leaf : m_groups.leaves[g]) n += m_plan.leaf_vertices(leaf);
            order.emplace_back(n, g);
        }
        std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        std::vector<tiling::TileJob> jobs;
        for (const auto& [n, g] : order) jobs.push_back(job_for(g));
        const auto t0 = std::chrono::steady_clock::now();
        std::size_t done = 0;
        std::vector<TileOutcome> results = tiling::run_jobs(ctx, jobs, m_tiling.threads, [&](const TileOutcome&) {
            if (progress) progress(++done, jobs.size());
        });
        m_stats.seconds_tiles += seconds_since(t0);
        m_stats.tile_runs += jobs.size();
        for (TileOutcome& oc : results) {
            ++m_runs[m_groups.leaves[oc.group].front()];
            if (oc.growths > 0) {
                m_stats.halo_growths += static_cast<std::size_t>(oc.growths);
                m_problems.push_back(Problem{oc.cascade_feature, ProblemCode::seam_cascade,
                    "a cascade of snaps reached the tile core from its halo; the halo grew to " +
                    std::to_string(oc.halo / m_options.tolerance) + " x tolerance" +
                    (oc.cascade_unbounded ? " and the cascade still reached it (left to the seam check)" : ""),
                    oc.cascade_x, oc.cascade_y});
            }
            m_stats.unbounded_cascades += oc.cascade_unbounded ? 1 : 0;
            m_outcomes[oc.group] = std::move(oc);
        }
        const auto t1 = std::chrono::steady_clock::now();
        const auto pairs = check_seams();
        m_stats.seconds_stitch += seconds_since(t1);
        if (pairs.empty()) break;
        merge(pairs, pending);
    }
    const auto t2 = std::chrono::steady_clock::now();
    assemble(out);
    m_stats.tiles = m_outcomes.size();
    m_stats.seconds_stitch += seconds_since(t2);
    std::stable_sort(m_problems.begin(), m_problems.end(), [](const Problem& a, const Problem& b) {
        return a.feature_id != b.feature_id ? a.feature_id < b.feature_id : a.code < b.code;
    });
    res.problems = std::move(m_problems);
    out.stitch = m_stats;
    return out;
}

} // namespace

TiledResult snap_tiled(const std::vector<Feature>& features, const SnapOptions& options, const TilingOptions& tiling,
                       const TileProgress& progress)
{
    if (const std::string msg = validate(options); !msg.empty()) throw std::invalid_argument(msg);
    if (!(tiling.halo_factor >= 2) || !std::isfinite(tiling.halo_factor))
        throw std::invalid_argument("halo factor must be finite and >= 2, got " + std::to_string(tiling.halo_factor));
    if (tiling.plan.tile_size < 0 || !std::isfinite(tiling.plan.tile_size))
        throw std::invalid_argument("tile size must be finite and > 0, got " + std::to_string(tiling.plan.tile_size));
    if (tiling.max_growth < 0) throw std::invalid_argument("max halo growth must be >= 0");
    return Stitcher(features, options, tiling).run(progress);
}

} // namespace trisnap::stitch
