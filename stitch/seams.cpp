#include "stitch/seams.hpp"

#include "stitch/tile_result.hpp"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <set>

namespace trisnap::stitch {
namespace {

std::vector<SeamEdge> read_seams(const tiling::WorkStore& store, std::size_t group)
{
    std::vector<SeamEdge> out;
    const std::unique_ptr<tiling::InFile> file = store.open(files::seams(group));
    tiling::RecordReader reader(*file, 1 << 18);
    std::string record;
    while (reader.next(record)) {
        tiling::ByteReader r(record, "seam");
        out.push_back(get_seam_edge(r));
    }
    return out;
}

class SeamChecker {
public:
    SeamChecker(const tiling::WorkStore& store, const TileLayout& layout, const Groups& groups,
                const std::vector<std::uint64_t>& dropped)
        : m_store(store), m_layout(layout), m_groups(groups), m_dropped(dropped)
    {
    }
    /// The groups whose check needs g's seam edges: g itself (its own check compares every
    /// edge it produced) when it has any, and the groups its owned edges come near (they read
    /// them as the stitched layer). An edge g does not own matters to no other group's check, so
    /// it does not make them read g's file: a tile's long artificial detour edges (outside the
    /// data, owned by nobody) came near 472 of 512 leaves on a 10 M layer, and every one of
    /// them read that tile's whole file, which made the seam check grow with the square of the
    /// tiles (24,134 file reads for 512 tiles).
    std::vector<std::size_t> near_groups(std::size_t g) const
    {
        std::vector<std::size_t> out;
        const std::vector<SeamEdge> edges = read_seams(m_store, g);
        if (!edges.empty()) {
            out.push_back(g);
        }
        for (const SeamEdge& e : edges) {
            if (e.owned) {
                for (std::uint32_t leaf : e.near) {
                    out.push_back(m_groups.of_leaf[leaf]);
                }
            }
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
    /// The groups to merge with g, and a 301 when there are any. `sources`: the groups whose
    /// seam edges come near g.
    void check(std::size_t g, const std::vector<std::size_t>& sources, std::set<std::pair<std::size_t, std::size_t>>& pairs,
               std::vector<std::pair<std::uint64_t, Problem>>& problems) const;

private:
    // Groups of the leaves an edge is near, when there are at least two (else empty).
    void groups_near(const SeamEdge& e, std::vector<std::size_t>& out) const
    {
        out.clear();
        for (std::uint32_t leaf : e.near) {
            out.push_back(m_groups.of_leaf[leaf]);
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        if (out.size() < 2) {
            out.clear();
        }
    }
    std::size_t owner(const DirectedEdge& e) const
    {
        return m_groups.of_leaf[m_layout.plan.leaf_of(0.5 * (e.a.x + e.b.x), 0.5 * (e.a.y + e.b.y))];
    }

    const tiling::WorkStore& m_store;
    const TileLayout& m_layout;
    const Groups& m_groups;
    const std::vector<std::uint64_t>& m_dropped;
};

void SeamChecker::check(std::size_t g, const std::vector<std::size_t>& sources,
                        std::set<std::pair<std::size_t, std::size_t>>& pairs,
                        std::vector<std::pair<std::uint64_t, Problem>>& problems) const
{
    std::vector<SeamEdge> produced;
    std::vector<SeamEdge> stitched;
    std::vector<std::size_t> near;
    for (std::size_t h : sources) {
        for (SeamEdge& e : read_seams(m_store, h)) {
            groups_near(e, near);
            if (!std::binary_search(near.begin(), near.end(), g) ||
                std::binary_search(m_dropped.begin(), m_dropped.end(), e.rank)) {
                continue;
            }
            if (h == g) {
                produced.push_back(e);
            }
            if (e.owned) {
                stitched.push_back(std::move(e));
            }
        }
    }
    std::sort(produced.begin(), produced.end(), seam_less);
    std::sort(stitched.begin(), stitched.end(), seam_less);
    std::vector<SeamEdge> differ;
    std::set_symmetric_difference(produced.begin(), produced.end(), stitched.begin(), stitched.end(),
                                  std::back_inserter(differ), seam_less);
    const std::size_t before = pairs.size();
    const SeamEdge* first = nullptr;
    const tiling::Box& x = m_layout.plan.extent();
    for (const SeamEdge& e : differ) {
        const double mx = 0.5 * (e.edge.a.x + e.edge.b.x);
        const double my = 0.5 * (e.edge.a.y + e.edge.b.y);
        if (!(x.xmin <= mx && mx <= x.xmax && x.ymin <= my && my <= x.ymax)) {
            continue; // produced outside the data: owned by nobody
        }
        const std::size_t o = owner(e.edge);
        if (o != g) {
            pairs.emplace(std::min(o, g), std::max(o, g));
            first = first ? first : &e;
        }
    }
    if (pairs.size() > before && first) {
        Problem p;
        p.code = ProblemCode::seam_mismatch;
        p.message = "tiles disagreed along a seam (" + std::to_string(differ.size()) +
                    " edges); they were merged and snapped again";
        p.x = 0.5 * (first->edge.a.x + first->edge.b.x);
        p.y = 0.5 * (first->edge.a.y + first->edge.b.y);
        problems.emplace_back(first->rank, p);
    }
}

} // namespace

namespace {

// Counts passes done from worker threads and reports them one call at a time.
class PassCount {
public:
    PassCount(const SeamProgress& progress, std::uint64_t total) : m_progress(progress), m_total(total) {}
    void one()
    {
        if (!m_progress) {
            return;
        }
        const std::lock_guard lock(m_mutex);
        m_progress(++m_done, m_total);
    }

private:
    const SeamProgress& m_progress;
    std::uint64_t m_total;
    std::uint64_t m_done = 0;
    std::mutex m_mutex;
};

} // namespace

SeamVerdict check_seams(const tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, int threads,
                        const std::vector<std::uint64_t>& dropped, const SeamProgress& progress)
{
    const std::vector<std::size_t> live = groups.live(layout);
    PassCount passes(progress, 2 * live.size());
    std::vector<std::set<std::pair<std::size_t, std::size_t>>> pairs(live.size());
    std::vector<std::vector<std::pair<std::uint64_t, Problem>>> problems(live.size());
    const SeamChecker checker(store, layout, groups, dropped);
    // Which groups' seam edges each group's check reads (an owned edge may be long: its owner's
    // core need not touch the group it comes near).
    std::vector<std::vector<std::size_t>> near(live.size());
    const int n = threads > 0 ? threads : tbb::info::default_concurrency();
    tbb::task_arena(n).execute([&] {
        tbb::parallel_for(std::size_t{0}, live.size(), [&](std::size_t i) {
            near[i] = checker.near_groups(live[i]);
            passes.one();
        });
    });
    std::map<std::size_t, std::vector<std::size_t>> sources; // group -> groups with edges near it
    for (std::size_t i = 0; i < live.size(); ++i) {
        for (std::size_t k : near[i]) {
            sources[k].push_back(live[i]);
        }
    }
    tbb::task_arena(n).execute([&] {
        tbb::parallel_for(std::size_t{0}, live.size(), [&](std::size_t i) {
            auto it = sources.find(live[i]);
            if (it != sources.end()) {
                checker.check(live[i], it->second, pairs[i], problems[i]);
            }
            passes.one();
        });
    });
    SeamVerdict out;
    std::set<std::pair<std::size_t, std::size_t>> all;
    for (std::size_t i = 0; i < live.size(); ++i) {
        all.insert(pairs[i].begin(), pairs[i].end());
        out.problems.insert(out.problems.end(), problems[i].begin(), problems[i].end());
    }
    out.pairs.assign(all.begin(), all.end());
    return out;
}

std::vector<std::size_t> merge_groups(tiling::WorkStore& store, Groups& groups,
                                      const std::vector<std::pair<std::size_t, std::size_t>>& pairs)
{
    std::map<std::size_t, std::size_t> parent;
    auto find = [&](std::size_t x) {
        while (parent.count(x) && parent[x] != x) {
            x = parent[x];
        }
        return x;
    };
    for (auto [a, b] : pairs) {
        const std::size_t ra = find(a);
        const std::size_t rb = find(b);
        parent.try_emplace(ra, ra);
        parent.try_emplace(rb, rb);
        if (ra != rb) {
            parent[std::max(ra, rb)] = std::min(ra, rb);
        }
    }
    std::map<std::size_t, std::vector<std::size_t>> merged; // root -> old groups
    for (const auto& [g, p] : parent) {
        merged[find(g)].push_back(g);
    }
    std::vector<std::size_t> added;
    for (auto& [root, olds] : merged) {
        const std::size_t id = groups.leaves.size();
        std::vector<std::size_t> leaves;
        double halo = 0;
        std::uint32_t runs = 0;
        for (std::size_t g : olds) {
            leaves.insert(leaves.end(), groups.leaves[g].begin(), groups.leaves[g].end());
            groups.leaves[g].clear();
            halo = std::max(halo, groups.halo[g]);
            runs = std::max(runs, groups.runs[g]);
            store.remove(files::result(g));
            store.remove(files::seams(g));
        }
        std::sort(leaves.begin(), leaves.end());
        for (std::size_t leaf : leaves) {
            groups.of_leaf[leaf] = id;
        }
        groups.leaves.push_back(std::move(leaves));
        groups.halo.push_back(halo);
        groups.runs.push_back(runs);
        groups.seam_merges += olds.size() - 1;
        added.push_back(id);
    }
    return added;
}

} // namespace trisnap::stitch
