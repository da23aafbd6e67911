// A tile whose engine failed (with OnError::skip): retried merged with its neighbours, then
// untiled in its region, and when that fails too, committed as failed with its features reported
// (TileRunner::fail, and the FIDs the messages name).
#include "stitch/tiled_snap_impl.hpp"

#include "stitch/seams.hpp"
#include "stitch/spool.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace trisnap::stitch {

void TileRunner::fail(std::size_t group, const std::string& reason) const
{
    const tiling::TileJobInput in = gather(group, m_groups.halo[group]);
    TileReport report;
    report.id = m_groups.leaves[group].front();
    report.leaves = m_groups.leaves[group].size();
    report.core = group_core(m_layout, m_groups, group);
    report.halo = m_groups.halo[group];
    report.features = in.features.size();
    report.input_vertices = in.vertices;
    report.failed = true;
    report.failure = reason;
    std::vector<std::pair<std::uint64_t, const tiling::TileFeature*>> by_rank;
    for (const tiling::TileFeature& f : in.features) {
        by_rank.emplace_back(f.rank, &f);
    }
    std::sort(by_rank.begin(), by_rank.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    report.problems = by_rank.size();
    const std::string features = describe(in.features);
    std::vector<Piece> pieces;
    for (const auto& [rank, f] : by_rank) {
        Piece piece;
        piece.rank = rank;
        Problem p;
        p.feature_id = f->feature.id;
        p.code = ProblemCode::tile_failed;
        p.message = "tile " + std::to_string(report.id) + " (" + features + ") failed " + reason +
                    "; not written (--on-error skip)";
        const Geometry& g = f->feature.geometry;
        const Path* first = !g.polygons.empty() && !g.polygons[0].rings.empty() ? &g.polygons[0].rings[0]
                            : !g.lines.empty()                                  ? &g.lines[0]
                                                                                : nullptr;
        p.x = first && !first->empty() ? first->front().x : std::nan("");
        p.y = first && !first->empty() ? first->front().y : std::nan("");
        piece.problems.push_back(std::move(p));
        pieces.push_back(std::move(piece));
    }
    write_files(group, report, pieces, {});
}

std::string TileRunner::describe_features(std::size_t group) const
{
    if (spool_cut_to_outlines(m_store)) {
        // A plan of one leaf whose spool is cut: its bucket is every feature with a point that
        // was not rejected (the leaf reaches round the whole layer); an outline has the FID.
        std::vector<std::int64_t> fids;
        SpooledFeatures in(m_store, true);
        detail::CleanFeature cf;
        bool has_z = false;
        while (in.next(cf, has_z)) {
            if (!cf.rejected && !box_of(cf).empty()) {
                fids.push_back(cf.id);
            }
        }
        return describe_fids(std::move(fids));
    }
    return describe(gather(group, m_groups.halo[group]).features);
}

std::string TileRunner::describe(const std::vector<tiling::TileFeature>& features) const
{
    std::vector<std::int64_t> fids;
    std::unique_ptr<FeatureLookup> lookup; // only when the engine's ids are not the FIDs
    for (const tiling::TileFeature& f : features) {
        if (m_meta.fids_unique) {
            fids.push_back(f.feature.id);
            continue;
        }
        if (!lookup) {
            lookup = std::make_unique<FeatureLookup>(m_store);
        }
        bool has_z = false;
        fids.push_back(lookup->at(f.rank, has_z).id);
    }
    return describe_fids(std::move(fids));
}

std::string TileRunner::describe_fids(std::vector<std::int64_t> fids)
{
    constexpr std::size_t k_named = 8;
    std::sort(fids.begin(), fids.end());
    std::string text = std::to_string(fids.size()) + (fids.size() == 1 ? " feature: FID " : " features: FIDs ");
    for (std::size_t k = 0; k < fids.size() && k < k_named; ++k) {
        text += (k ? ", " : "") + std::to_string(fids[k]);
    }
    if (fids.size() > k_named) {
        text += " and " + std::to_string(fids.size() - k_named) + " more";
    }
    return text;
}

// The last try of each failed group: its region untiled, every feature meeting it given whole
// (an untiled run's view of it: no shortcut or detour edge), one group at a time with the whole
// memory pool. It goes through the seam check like any tile (a disagreement merges it with the
// neighbour, and a merged run that fails comes back here, larger each time). When it fails too,
// the group is committed as failed: its features are reported (303) with the tries and reasons.
void TiledRun::Impl::retry_whole(const std::vector<std::pair<std::size_t, std::string>>& failed, const std::string& tried)
{
    const TileRunner runner(store, layout, groups, meta, options, tiling.max_growth);
    for (const auto& [g, reason] : failed) {
        const std::string again = run_one(runner, g, [](std::size_t, std::size_t) {}, TileInputMode::whole);
        ++groups.runs[g];
        if (again.empty()) {
            ++stats.tile_runs;
            continue;
        }
        runner.fail(g, tried + " (" + reason + ") and untiled in its region (" + again + ")");
    }
}

// The features failed tiles dropped (their results' pieces), ascending. Reads only the first
// record of the other results.
std::vector<std::uint64_t> TiledRun::Impl::dropped_ranks() const
{
    std::vector<std::uint64_t> out;
    std::string record;
    for (std::size_t g : groups.live(layout)) {
        if (!store.exists(files::result(g))) {
            continue;
        }
        const std::unique_ptr<tiling::InFile> file = store.open(files::result(g));
        tiling::RecordReader reader(*file, 4096);
        if (!reader.next(record)) {
            continue;
        }
        tiling::ByteReader r(record, "tile report");
        if (!get_tile_report(r).failed) {
            continue;
        }
        while (reader.next(record)) {
            tiling::ByteReader pr(record, "piece");
            out.push_back(get_piece(pr).rank);
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// Each failed group merged with every live group whose core touches its own, and run again
// once. When the merged tile fails too, it is split back into the groups it was made of: the
// neighbours run again as they were (the same result as before), and the groups that failed
// alone get their last try (retry_whole). A merge the memory pool cannot hold is not tried.
void TiledRun::Impl::retry_merged(const std::vector<std::pair<std::size_t, std::string>>& failed, const TileProgress& progress)
{
    const TileRunner runner(store, layout, groups, meta, options, tiling.max_growth);
    const std::vector<std::size_t> live = groups.live(layout);
    const std::uint64_t cap = max_tile_vertices();
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    std::map<std::size_t, std::string> reasons; // failed alone: group -> message
    std::vector<std::pair<std::size_t, std::string>> alone; // no merge possible: straight to the last try
    for (const auto& [g, reason] : failed) {
        const tiling::Box core = group_core(layout, groups, g);
        std::uint64_t vertices = runner.vertices(g);
        std::vector<std::size_t> neighbours;
        for (std::size_t h : live) {
            const tiling::Box other = group_core(layout, groups, h);
            if (h != g && other.xmin <= core.xmax && core.xmin <= other.xmax && other.ymin <= core.ymax && core.ymin <= other.ymax) {
                neighbours.push_back(h);
                vertices += runner.vertices(h);
            }
        }
        if (neighbours.empty() || (cap > 0 && vertices > cap)) {
            alone.emplace_back(g, reason);
            continue;
        }
        reasons.emplace(g, reason);
        for (std::size_t h : neighbours) {
            pairs.emplace_back(std::min(g, h), std::max(g, h));
        }
    }
    retry_whole(alone, "alone");
    if (pairs.empty()) {
        save_groups();
        return;
    }
    // What each merged group is made of, to split it back.
    struct Part {
        std::vector<std::size_t> leaves;
        double halo;
        std::uint32_t runs;
        std::string reason; ///< "" for a neighbour that did not fail
    };
    std::map<std::size_t, Part> parts; // old group -> part
    for (const auto& [a, b] : pairs) {
        for (std::size_t g : {a, b}) {
            auto it = reasons.find(g);
            parts.try_emplace(g, Part{groups.leaves[g], groups.halo[g], groups.runs[g], it == reasons.end() ? "" : it->second});
        }
    }
    const std::size_t seam_merges = groups.seam_merges;
    const std::vector<std::size_t> added = merge_groups(store, groups, pairs);
    groups.seam_merges = seam_merges; // not a seam that disagreed
    save_groups();
    const std::vector<std::pair<std::size_t, std::string>> again = run_once(added, progress);
    if (again.empty()) {
        return;
    }
    std::vector<std::size_t> rerun;
    std::vector<std::pair<std::size_t, std::string>> dropped;
    for (const auto& [merged, message] : again) {
        const std::vector<std::size_t> leaves = groups.leaves[merged];
        groups.leaves[merged].clear();
        for (const auto& [old, part] : parts) {
            if (std::find(leaves.begin(), leaves.end(), part.leaves.front()) == leaves.end()) {
                continue;
            }
            const std::size_t id = groups.leaves.size();
            for (std::size_t leaf : part.leaves) {
                groups.of_leaf[leaf] = id;
            }
            groups.leaves.push_back(part.leaves);
            groups.halo.push_back(part.halo);
            groups.runs.push_back(part.runs);
            if (part.reason.empty()) {
                rerun.push_back(id);
            } else {
                dropped.emplace_back(id, part.reason);
            }
        }
    }
    save_groups();
    retry_whole(dropped, "alone and merged with its neighbours");
    save_groups(); // the runs the last tries added
    run_groups(rerun, progress, false);
}

} // namespace trisnap::stitch
