#include "stitch/tile_run.hpp"

#include "core/assemble.hpp"
#include "tiling/tile_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace trisnap::stitch {
namespace {

using tiling::Box;

Box edge_box(const DirectedEdge& e)
{
    Box b;
    b.add(e.a.x, e.a.y);
    b.add(e.b.x, e.b.y);
    return b;
}

bool inside_region(const Region& r, const Box& b)
{
    return r.xmin <= b.xmin && b.xmax < r.xmax && r.ymin <= b.ymin && b.ymax < r.ymax;
}

// The codes a tile's own evidence decides (the rest is judged on the stitched feature).
bool kept_from_tile(ProblemCode code)
{
    return code == ProblemCode::self_intersection || code == ProblemCode::not_converged ||
           code == ProblemCode::separation_not_reached || code == ProblemCode::thin_part_collapsed;
}

// Pieces and seam edges of one tile's output.
class ResultBuilder {
public:
    ResultBuilder(const TileLayout& layout, const Groups& groups, std::size_t group)
        : m_layout(layout), m_groups(groups), m_group(group)
    {
    }
    /// Takes `fo`'s geometry when the piece keeps it whole.
    void add_feature(std::uint64_t rank, bool intact, FeatureOutput& fo, const std::vector<std::uint64_t>& ranks);
    void add_problem(std::size_t position, const Problem& p);
    std::vector<Piece>& pieces() { return m_pieces; }
    std::vector<SeamEdge>& seams() { return m_seams; }
    std::size_t owned() const { return m_owned; }
    std::size_t problems() const { return m_problems; }

private:
    bool mine(std::size_t leaf) const { return m_groups.of_leaf[leaf] == m_group; }
    bool owns(const DirectedEdge& e) const;
    bool in_a_core(const Polygon& poly) const;
    bool deep_in_a_core(const Geometry& g) const;
    void seam_edge(std::uint64_t rank, const DirectedEdge& e, bool owned);

    const TileLayout& m_layout;
    const Groups& m_groups;
    std::size_t m_group;
    std::vector<Piece> m_pieces; ///< one per input feature, in order
    std::vector<SeamEdge> m_seams;
    std::vector<DirectedEdge> m_edges;
    std::vector<std::size_t> m_near;
    std::size_t m_owned = 0;
    std::size_t m_problems = 0;
};

// An edge belongs to the tile whose core holds its midpoint (none outside the data extent:
// only artificial detour edges lie there).
bool ResultBuilder::owns(const DirectedEdge& e) const
{
    const double mx = 0.5 * (e.a.x + e.b.x);
    const double my = 0.5 * (e.a.y + e.b.y);
    const Box& x = m_layout.plan.extent();
    if (!(x.xmin <= mx && mx <= x.xmax && x.ymin <= my && my <= x.ymax)) {
        return false;
    }
    return mine(m_layout.plan.leaf_of(mx, my));
}

void ResultBuilder::seam_edge(std::uint64_t rank, const DirectedEdge& e, bool owned)
{
    const Box b = edge_box(e).expanded(m_layout.seam_band);
    const std::size_t home = m_layout.plan.leaf_of(0.5 * (e.a.x + e.b.x), 0.5 * (e.a.y + e.b.y));
    if (inside_region(m_layout.plan.core(home), b) && mine(home)) {
        return; // deep inside one of this tile's leaves: near no seam
    }
    m_near.clear();
    m_layout.plan.query(b, m_near);
    if (std::all_of(m_near.begin(), m_near.end(), [&](std::size_t leaf) { return mine(leaf); })) {
        return;
    }
    SeamEdge s;
    s.rank = rank;
    s.edge = e;
    s.owned = owned;
    s.near.assign(m_near.begin(), m_near.end());
    m_seams.push_back(std::move(s));
}

// A polygon of the tile's output is finished when it lies inside the core of one of the
// tile's leaves (so every edge of the feature lying inside it has its midpoint in that core:
// the tile traced them all with it) and the tile owns every edge of it: it goes to the stitch as
// a polygon, not as edges to trace again. An edge from outside can still end at one of its
// vertices (owned by another tile); the stitch then traces it again (assemble_polygons'
// `finished`).
bool ResultBuilder::in_a_core(const Polygon& poly) const
{
    Box b;
    for (const Coord& c : poly.rings.front()) {
        b.add(c.x, c.y);
    }
    const std::size_t leaf = m_layout.plan.leaf_of(b.xmin, b.ymin);
    return mine(leaf) && inside_region(m_layout.plan.core(leaf), b);
}

// Whether the geometry's box, grown by the seam band, lies inside the core of one of the tile's
// leaves and inside the layer's extent. Then the tile owns each of its edges (their midpoints
// are in that core and the extent) and none is near a seam (each edge's grown box is inside
// the core of the leaf its midpoint is in): what add_feature's edge by edge tests would find.
bool ResultBuilder::deep_in_a_core(const Geometry& g) const
{
    const Box b = tiling::box_of(g);
    if (b.empty() || !m_layout.plan.extent().contains(b)) {
        return false;
    }
    const std::size_t leaf = m_layout.plan.leaf_of(b.xmin, b.ymin);
    return mine(leaf) && inside_region(m_layout.plan.core(leaf), b.expanded(m_layout.seam_band));
}

void ResultBuilder::add_feature(std::uint64_t rank, bool intact, FeatureOutput& fo,
                                const std::vector<std::uint64_t>& ranks)
{
    Piece piece;
    piece.rank = rank;
    piece.displacement = fo.max_displacement;
    piece.shared = fo.shared;
    for (SharedBoundary& s : piece.shared) {
        s.other_position = ranks[s.other_position]; // the tile's input position -> the rank
    }
    piece.has_z = fo.geometry.has_z;
    piece.geometry.has_z = fo.geometry.has_z;
    // Most features of a tile lie deep inside one of its leaves: whole, without their edges
    // listed and tested one by one (Andorra x43 untiled: the edge by edge tests and the copy of
    // the geometry were 5 % of the run).
    if (intact && deep_in_a_core(fo.geometry)) {
        std::size_t edges = 0;
        for (const Polygon& poly : fo.geometry.polygons) {
            for (const Path& r : poly.rings) edges += r.empty() ? 0 : r.size() - 1;
        }
        for (const Path& l : fo.geometry.lines) edges += l.empty() ? 0 : l.size() - 1;
        if (edges > 0) {
            m_owned += edges;
            piece.whole = true;
            piece.geometry = std::move(fo.geometry);
            m_pieces.push_back(std::move(piece));
            return;
        }
    }
    std::size_t total = 0;
    std::size_t owned = 0;
    auto add_edges = [&](bool may_finish) {
        const std::size_t before = piece.edges.size();
        for (const DirectedEdge& e : m_edges) {
            const bool mine = owns(e);
            if (mine) {
                piece.edges.push_back(e);
            }
            seam_edge(rank, e, mine);
        }
        const std::size_t added = piece.edges.size() - before;
        total += m_edges.size();
        owned += added;
        const bool finished = may_finish && added == m_edges.size() && added > 0;
        if (finished) {
            piece.edges.resize(before);
        }
        return finished;
    };
    for (const Polygon& poly : fo.geometry.polygons) {
        m_edges.clear();
        append_ring_edges(poly, m_edges);
        if (add_edges(in_a_core(poly))) {
            piece.geometry.polygons.push_back(poly);
        }
    }
    for (const Path& l : fo.geometry.lines) {
        m_edges.clear();
        for (std::size_t i = 0; i + 1 < l.size(); ++i) {
            m_edges.push_back(DirectedEdge{l[i], l[i + 1]});
        }
        add_edges(false);
    }
    m_owned += owned;
    if (intact && total > 0 && owned == total) {
        piece.whole = true;
        piece.edges.clear();
        piece.geometry = std::move(fo.geometry);
    } else if (!piece.geometry.polygons.empty()) {
        piece.geometry.type = piece.geometry.polygons.size() == 1 ? Geometry::Type::Polygon : Geometry::Type::MultiPolygon;
    }
    m_pieces.push_back(std::move(piece));
}

// 205/207/209 count where they happen; 105 from any tile (each tile reports crossings only in
// its core; the stitch keeps one per feature).
void ResultBuilder::add_problem(std::size_t position, const Problem& p)
{
    if (!kept_from_tile(p.code)) {
        return;
    }
    if (p.code != ProblemCode::self_intersection && !mine(m_layout.plan.leaf_of(p.x, p.y))) {
        return;
    }
    m_pieces[position].problems.push_back(p);
    ++m_problems;
}

bool worth_keeping(const Piece& p)
{
    return p.whole || !p.edges.empty() || !p.geometry.polygons.empty() || p.displacement > 0 || !p.problems.empty() ||
           !p.shared.empty();
}

} // namespace

TileRunner::TileRunner(tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, const SpoolMeta& meta,
                       const SnapOptions& options, int max_growth, bool cut_spool)
    : m_store(store), m_layout(layout), m_groups(groups), m_meta(meta), m_options(options), m_max_growth(max_growth),
      m_cut_spool(cut_spool)
{
}

std::uint64_t TileRunner::vertices(std::size_t group) const
{
    std::uint64_t n = 0;
    for (std::size_t leaf : m_groups.leaves[group]) {
        n += m_layout.bucket_vertices[leaf];
    }
    return n;
}

tiling::TileJobInput TileRunner::gather(std::size_t group, double halo, TileInputMode mode) const
{
    const std::vector<std::size_t>& leaves = m_groups.leaves[group];
    if (leaves.size() != 1 || halo != m_layout.halo || mode == TileInputMode::whole) {
        return gather_wide(group, halo, mode);
    }
    tiling::TileJobInput in;
    in.features = read_bucket(m_store, m_layout, m_meta, leaves[0]);
    in.reach = m_layout.reach[leaves[0]];
    in.vertices = m_layout.bucket_vertices[leaves[0]];
    return in;
}

// Every feature meeting a box is in the bucket of some leaf whose core meets the box (a leaf's
// bucket holds everything meeting its core, and more). The reach is grown from the features'
// own edges (read back from features.bin: a bucket's cut features carry detour edges that
// must not count), then they are cut to it; or (TileInputMode::whole) given whole: cut to a
// box that holds every one of them, which leaves them intact.
tiling::TileJobInput TileRunner::gather_wide(std::size_t group, double halo, TileInputMode mode) const
{
    const Box core = group_core(m_layout, m_groups, group);
    FeatureLookup lookup(m_store);
    std::map<std::uint64_t, std::pair<detail::CleanFeature, bool>> seen; // rank -> (feature, has_z)
    auto features_meeting = [&](const Box& b) {
        std::vector<std::size_t> leaves;
        m_layout.plan.query(b, leaves);
        std::set<std::uint64_t> ranks;
        for (std::size_t leaf : leaves) {
            for (const tiling::TileFeature& f : read_bucket(m_store, m_layout, m_meta, leaf)) {
                ranks.insert(f.rank);
            }
        }
        for (std::uint64_t rank : ranks) {
            if (!seen.count(rank)) {
                bool has_z = false;
                detail::CleanFeature cf = lookup.at(rank, has_z);
                seen.emplace(rank, std::make_pair(std::move(cf), has_z));
            }
        }
        return ranks;
    };
    const Box r0 = core.expanded(halo);
    Box reach = r0;
    for (std::uint64_t rank : features_meeting(r0)) {
        const detail::CleanFeature& cf = seen.at(rank).first;
        grow_reach(cf, box_of(cf), r0, reach);
    }
    tiling::TileJobInput in;
    in.reach = reach.expanded(halo);
    const std::set<std::uint64_t> ranks = features_meeting(in.reach);
    Box cut_to = in.reach;
    for (std::uint64_t rank : ranks) {
        if (mode == TileInputMode::whole) {
            cut_to.add(box_of(seen.at(rank).first));
        }
    }
    const tiling::TileCutter cutter(cut_to, tiling::detour_frame(m_meta.sample.extent, cut_to));
    for (std::uint64_t rank : ranks) {
        const auto& [cf, has_z] = seen.at(rank);
        tiling::TileFeature tf;
        if (!cutter.cut(cf, has_z, tf.feature, tf.intact)) {
            continue;
        }
        tf.rank = rank;
        tf.feature.id = engine_id(m_meta, cf);
        in.vertices += tiling::engine_vertices(tf.feature.geometry);
        in.features.push_back(std::move(tf));
    }
    return in;
}

void TileRunner::commit(std::size_t group, tiling::TileOutcome& oc, TileReport& report) const
{
    ResultBuilder builder(m_layout, m_groups, group);
    std::unordered_map<std::int64_t, std::size_t> position;
    for (std::size_t k = 0; k < oc.ranks.size(); ++k) {
        builder.add_feature(oc.ranks[k], oc.intact[k], oc.result.features[k], oc.ranks);
        position.emplace(oc.result.features[k].id, k);
    }
    for (const Problem& p : oc.result.problems) {
        if (auto it = position.find(p.feature_id); it != position.end()) {
            builder.add_problem(it->second, p);
        }
    }
    report.output_edges_owned = builder.owned();
    report.problems = builder.problems();
    write_files(group, report, builder.pieces(), builder.seams());
}

// result-<group>: the report, then the pieces worth keeping (in rank order); seams-<group>.
void TileRunner::write_files(std::size_t group, const TileReport& report, const std::vector<Piece>& pieces,
                             const std::vector<SeamEdge>& seams) const
{
    std::string record;
    {
        const std::unique_ptr<tiling::OutFile> file = m_store.create(files::result(group));
        tiling::RecordWriter writer(*file);
        tiling::ByteWriter w(record);
        put_tile_report(w, report);
        writer.write(record);
        for (const Piece& p : pieces) {
            if (worth_keeping(p)) {
                record.clear();
                put_piece(w, p);
                writer.write(record);
            }
        }
        file->commit();
    }
    const std::unique_ptr<tiling::OutFile> file = m_store.create(files::seams(group));
    tiling::RecordWriter writer(*file);
    tiling::ByteWriter w(record);
    for (const SeamEdge& s : seams) {
        record.clear();
        put_seam_edge(w, s);
        writer.write(record);
    }
    file->commit();
}

namespace {

// Fault injection for the tests of --on-error (an engine that never fails cannot test it):
// TRISNAP_FAIL_TILES="3,7/1,9/cut" makes the tile holding plan leaf 3 throw whenever it runs,
// the one holding leaf 7 only while it is that leaf alone (so its retry merged with its
// neighbours goes through), and the one holding leaf 9 whenever its features are cut (alone or
// merged: its retry untiled in its region goes through). Read on every call: tests set it per run.
void injected_failure(const std::vector<std::size_t>& leaves, TileInputMode mode)
{
    const char* spec = std::getenv("TRISNAP_FAIL_TILES");
    if (spec == nullptr || *spec == '\0') {
        return;
    }
    std::istringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        const std::size_t slash = item.find('/');
        const std::string when = slash == std::string::npos ? "" : item.substr(slash + 1);
        std::size_t leaf = 0;
        try {
            leaf = std::stoull(item.substr(0, slash));
        } catch (const std::exception&) {
            throw std::invalid_argument("TRISNAP_FAIL_TILES: '" + item + "' is not a leaf number");
        }
        const bool now = when.empty() || (when == "1" && leaves.size() == 1) || (when == "cut" && mode == TileInputMode::cut);
        if (now && std::find(leaves.begin(), leaves.end(), leaf) != leaves.end()) {
            throw std::logic_error("injected failure of tile " + std::to_string(leaf) + " (TRISNAP_FAIL_TILES)");
        }
    }
}

} // namespace

TileReport TileRunner::run(std::size_t group, const SnapProgress& progress, TileInputMode mode,
                           std::uint64_t max_vertices) const
{
    const tiling::Gather gather_input = [&](double h) {
        tiling::TileJobInput in = gather(group, h, mode);
        if (m_cut_spool) {
            cut_spool_to_outlines(m_store);
        }
        // As the engine would fail: after its input was gathered (and the spool cut).
        injected_failure(m_groups.leaves[group], mode);
        if (mode == TileInputMode::whole && max_vertices > 0 && in.vertices > max_vertices) {
            throw std::length_error("its features whole hold " + std::to_string(in.vertices) +
                                    " vertices, more than the memory limit holds in one triangulation");
        }
        return in;
    };
    tiling::TileJob job;
    job.core = group_core(m_layout, m_groups, group);
    job.report_region = group_region(m_layout, m_groups, group);
    job.halo = m_groups.halo[group];
    job.max_growth = m_max_growth;
    SnapOptions options = m_options;
    options.progress = progress;
    if (m_groups.leaves[group].size() > 1) {
        for (std::size_t leaf : m_groups.leaves[group]) {
            options.report_cores.push_back(m_layout.plan.core(leaf));
        }
    }
    if (const tiling::Box& x = m_layout.plan.extent(); !x.empty()) {
        options.data_extent = Region{x.xmin, x.ymin, x.xmax, x.ymax}; // closed for this use
    }
    tiling::TileOutcome oc = tiling::run_tile(job, options, gather_input);
    TileReport report;
    report.id = m_groups.leaves[group].front();
    report.leaves = m_groups.leaves[group].size();
    report.core = job.core;
    report.halo = oc.halo;
    report.growths = oc.growths;
    report.cascade_unbounded = oc.cascade_unbounded;
    report.cascade_x = oc.cascade_x;
    report.cascade_y = oc.cascade_y;
    for (std::size_t k = 0; k < oc.ranks.size(); ++k) {
        if (oc.growths > 0 && oc.result.features[k].id == oc.cascade_feature) {
            report.cascade_rank = oc.ranks[k];
            break;
        }
    }
    report.features = oc.ranks.size();
    report.input_vertices = oc.input_vertices;
    report.seconds = oc.seconds;
    report.stats = oc.result.stats;
    commit(group, oc, report);
    return report;
}

} // namespace trisnap::stitch
