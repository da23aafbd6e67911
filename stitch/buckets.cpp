// make_buckets(): the tile plan, each leaf's reach box, each leaf's bucket (see spool.hpp).
#include "stitch/spool.hpp"

#include "tiling/records.hpp"
#include "tiling/tile_input.hpp"

#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <memory>

namespace trisnap::stitch {

using tiling::Box;

Box box_of(const detail::CleanFeature& cf)
{
    Box b;
    for (const auto& r : cf.rings) {
        b.add(tiling::box_of(r.points));
    }
    for (const auto& l : cf.lines) {
        b.add(tiling::box_of(l));
    }
    return b;
}

namespace {

// Calls f(p, q) for every edge of the feature (ring edges include the closing one).
template <class F>
void for_each_edge(const detail::CleanFeature& cf, F&& f)
{
    for (const auto& ring : cf.rings) {
        const std::size_t n = ring.points.size();
        for (std::size_t i = 0; i < n; ++i) {
            f(ring.points[i], ring.points[(i + 1) % n]);
        }
    }
    for (const auto& line : cf.lines) {
        for (std::size_t i = 0; i + 1 < line.size(); ++i) {
            f(line[i], line[i + 1]);
        }
    }
}

} // namespace

void grow_reach(const detail::CleanFeature& cf, const Box& feature_box, const Box& r0, Box& reach)
{
    if (!feature_box.intersects(r0) || r0.contains(feature_box)) {
        return;
    }
    // Path by path, as for the whole feature above: a path whose box misses r0 has no edge
    // meeting it, and one inside r0 adds nothing to a reach that starts as r0; only the others
    // are looked at edge by edge.
    const auto grow = [&](const std::vector<Coord>& path, bool closed) {
        const Box b = tiling::box_of(path);
        if (!b.intersects(r0) || r0.contains(b)) {
            return;
        }
        const std::size_t n = path.size();
        for (std::size_t i = 0; i + 1 < n || (closed && i < n); ++i) {
            const Coord& p = path[i];
            const Coord& q = path[(i + 1) % n];
            if (tiling::segment_meets_box(p, q, r0)) {
                reach.add(p.x, p.y);
                reach.add(q.x, q.y);
            }
        }
    };
    for (const auto& ring : cf.rings) {
        grow(ring.points, true);
    }
    for (const auto& line : cf.lines) {
        grow(line, false);
    }
}

namespace {

// A uniform grid over the data extent holding the leaves' reach boxes: the leaves whose R
// meets a feature's box, without looking at every leaf.
class ReachGrid {
public:
    ReachGrid(const std::vector<Box>& reach, const Box& extent);
    /// The leaves whose reach meets `b`, ascending. Const: the bucket pass asks from several
    /// threads at once.
    void query(const Box& b, std::vector<std::size_t>& out) const;

private:
    long cell(double v, double origin, long n) const
    {
        const double k = std::floor((v - origin) / m_step);
        return static_cast<long>(std::clamp(k, 0.0, static_cast<double>(n - 1)));
    }

    const std::vector<Box>& m_reach;
    Box m_extent;
    double m_step = 1;
    long m_nx = 1;
    long m_ny = 1;
    std::vector<std::vector<std::uint32_t>> m_cells;
};

ReachGrid::ReachGrid(const std::vector<Box>& reach, const Box& extent) : m_reach(reach), m_extent(extent)
{
    const double w = std::max(extent.width(), 0.0);
    const double h = std::max(extent.height(), 0.0);
    const double cells = 4.0 * static_cast<double>(std::max<std::size_t>(reach.size(), 1));
    m_step = std::sqrt(std::max(w * h, 1e-300) / cells);
    if (!(m_step > 0) || !std::isfinite(m_step)) {
        m_step = std::max({w, h, 1.0});
    }
    m_nx = std::clamp(static_cast<long>(w / m_step) + 1, 1L, 4096L);
    m_ny = std::clamp(static_cast<long>(h / m_step) + 1, 1L, 4096L);
    m_step = std::max({w / static_cast<double>(m_nx), h / static_cast<double>(m_ny), m_step * 1e-9});
    m_cells.resize(static_cast<std::size_t>(m_nx * m_ny));
    for (std::uint32_t k = 0; k < reach.size(); ++k) {
        const Box& r = reach[k];
        if (r.empty()) {
            continue;
        }
        for (long x = cell(r.xmin, extent.xmin, m_nx); x <= cell(r.xmax, extent.xmin, m_nx); ++x) {
            for (long y = cell(r.ymin, extent.ymin, m_ny); y <= cell(r.ymax, extent.ymin, m_ny); ++y) {
                m_cells[static_cast<std::size_t>(x * m_ny + y)].push_back(k);
            }
        }
    }
}

void ReachGrid::query(const Box& b, std::vector<std::size_t>& out) const
{
    out.clear();
    for (long x = cell(b.xmin, m_extent.xmin, m_nx); x <= cell(b.xmax, m_extent.xmin, m_nx); ++x) {
        for (long y = cell(b.ymin, m_extent.ymin, m_ny); y <= cell(b.ymax, m_extent.ymin, m_ny); ++y) {
            for (std::uint32_t k : m_cells[static_cast<std::size_t>(x * m_ny + y)]) {
                if (m_reach[k].intersects(b)) {
                    out.push_back(k);
                }
            }
        }
    }
    std::sort(out.begin(), out.end()); // a reach over several cells is found once per cell
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

/// `record` framed as tiling::RecordReader reads it, appended to `out`.
void frame_record(std::string& out, std::string_view record)
{
    const auto n = static_cast<std::uint32_t>(record.size());
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    out.append(record);
}

// Bucket records buffered per leaf and appended to the store in large blocks; a store in
// memory takes them at once (buffered, they would be copied twice).
class BucketWriter {
public:
    BucketWriter(tiling::WorkStore& store, std::size_t cap) : m_store(store), m_cap(store.on_disk() ? cap : 0) {}
    void add(std::size_t leaf, const tiling::TileFeature& f)
    {
        m_scratch.clear();
        tiling::ByteWriter w(m_scratch);
        tiling::put_tile_feature(w, f);
        m_framed.clear();
        frame_record(m_framed, m_scratch);
        add_framed(leaf, m_framed);
    }
    /// Records framed by frame_record(), for the leaf's bucket.
    void add_framed(std::size_t leaf, std::string_view records)
    {
        if (records.empty()) {
            return;
        }
        if (m_cap == 0) {
            m_store.append(files::bucket(leaf), records);
            return;
        }
        if (m_buffers.size() <= leaf) {
            m_buffers.resize(leaf + 1);
        }
        m_buffers[leaf].append(records);
        m_buffered += records.size();
        if (m_buffered > m_cap) {
            flush();
        }
    }
    void flush()
    {
        for (std::size_t leaf = 0; leaf < m_buffers.size(); ++leaf) {
            if (!m_buffers[leaf].empty()) {
                m_store.append(files::bucket(leaf), m_buffers[leaf]);
                m_buffers[leaf].clear();
                m_buffers[leaf].shrink_to_fit();
            }
        }
        m_buffered = 0;
    }

private:
    tiling::WorkStore& m_store;
    std::size_t m_cap; ///< 0: every add goes to the store at once
    std::vector<std::string> m_buffers;
    std::size_t m_buffered = 0;
    std::string m_scratch;
    std::string m_framed;
};

} // namespace

namespace {

/// What a leaf's bucket holds of one spooled feature: the feature cut to the leaf's reach, with
/// its rank and engine id. False when nothing of it is left.
bool bucket_entry(const tiling::TileCutter& cutter, const SpoolMeta& meta, const detail::CleanFeature& cf, bool has_z,
                  std::uint64_t rank, tiling::TileFeature& out)
{
    if (!cutter.cut(cf, has_z, out.feature, out.intact)) {
        return false;
    }
    out.rank = rank;
    out.feature.id = engine_id(meta, cf);
    return true;
}

std::unique_ptr<tiling::TileCutter> leaf_cutter(const TileLayout& layout, const SpoolMeta& meta, std::size_t leaf)
{
    const Box& R = layout.reach[leaf];
    return std::make_unique<tiling::TileCutter>(R, tiling::detour_frame(meta.sample.extent, R));
}

/// The bucket of a plan's only leaf, made from features.bin as bucket_pass() makes any other.
std::vector<tiling::TileFeature> whole_bucket(const tiling::WorkStore& store, const TileLayout& layout,
                                              const SpoolMeta& meta, std::size_t leaf)
{
    std::vector<tiling::TileFeature> out;
    const std::unique_ptr<tiling::TileCutter> cutter = leaf_cutter(layout, meta, leaf);
    SpooledFeatures in(store);
    detail::CleanFeature cf;
    bool has_z = false;
    tiling::TileFeature tf;
    for (std::uint64_t rank = 0; in.next(cf, has_z); ++rank) {
        const Box b = box_of(cf);
        if (!cf.rejected && !b.empty() && layout.reach[leaf].intersects(b) && bucket_entry(*cutter, meta, cf, has_z, rank, tf)) {
            out.push_back(std::move(tf));
        }
    }
    return out;
}

} // namespace

bool whole_spool_bucket(const TileLayout& layout) { return layout.plan.size() == 1; }

std::vector<tiling::TileFeature> read_bucket(const tiling::WorkStore& store, const TileLayout& layout, const SpoolMeta& meta,
                                             std::size_t leaf)
{
    if (whole_spool_bucket(layout)) {
        return whole_bucket(store, layout, meta, leaf);
    }
    std::vector<tiling::TileFeature> out;
    if (!store.exists(files::bucket(leaf))) {
        return out;
    }
    const std::unique_ptr<tiling::InFile> file = store.open(files::bucket(leaf));
    tiling::RecordReader reader(*file);
    std::string record;
    while (reader.next(record)) {
        tiling::ByteReader r(record, "bucket");
        out.push_back(tiling::get_tile_feature(r));
    }
    return out;
}

tiling::Box reach_box(const tiling::Box& core, double halo, const std::vector<tiling::TileFeature>& from)
{
    const Box r0 = core.expanded(halo);
    Box reach = r0;
    for (const tiling::TileFeature& f : from) {
        const detail::CleanFeature cf = as_clean(f.feature);
        grow_reach(cf, box_of(cf), r0, reach);
    }
    return reach.expanded(halo);
}

namespace {

/// A run of features.bin's records for the passes below: read in order, worked on by any
/// thread, what the work found taken in order. `Found` is the pass's own.
template <class Found>
struct SpoolBatch {
    std::uint64_t first = 0;          ///< the first record's rank
    std::string bytes;                ///< the records, one after the other
    std::vector<std::size_t> ends;    ///< where each ends in `bytes`
    Found found;
};

/// Runs a pass over features.bin on `threads` threads: `work(rank, feature, has_z, found)`
/// for each feature, on any thread (batches of them at once), then `take(found, last rank)`
/// for each batch in input order, on one thread at a time. What the pass makes of the
/// features therefore does not depend on the number of threads (nor on the batches: `take`
/// sees every feature's findings in input order). Batches hold at most about `batch_bytes` of
/// records (or one record), and at most 2 per thread are in flight; threads beyond the cores
/// are not asked for (each would add 2 batches in flight, and nothing else).
template <class Found, class Work, class Take>
void spool_pass(const tiling::WorkStore& store, int threads, std::size_t batch_bytes, const Work& work, const Take& take)
{
    using Batch = SpoolBatch<Found>;
    const std::unique_ptr<tiling::InFile> file = store.open(files::features);
    tiling::RecordReader reader(*file);
    std::string record;
    std::uint64_t rank = 0;
    bool more = true;
    const auto read = [&](tbb::flow_control& fc) -> std::shared_ptr<Batch> {
        auto batch = std::make_shared<Batch>();
        batch->first = rank;
        while (more && (batch->ends.empty() || batch->bytes.size() < batch_bytes)) {
            more = reader.next(record);
            if (more) {
                batch->bytes += record;
                batch->ends.push_back(batch->bytes.size());
                ++rank;
            }
        }
        if (batch->ends.empty()) {
            fc.stop();
            return nullptr;
        }
        return batch;
    };
    const auto run = [&](std::shared_ptr<Batch> batch) {
        detail::CleanFeature cf;
        bool has_z = false;
        std::size_t start = 0;
        for (std::size_t i = 0; i < batch->ends.size(); ++i) {
            tiling::ByteReader r(std::string_view(batch->bytes).substr(start, batch->ends[i] - start), "feature");
            cf = tiling::get_clean_feature(r, has_z);
            work(batch->first + i, cf, has_z, batch->found);
            start = batch->ends[i];
        }
        batch->bytes.clear();
        batch->bytes.shrink_to_fit(); // the records go before the batch waits for its turn
        return batch;
    };
    const auto use = [&](std::shared_ptr<Batch> batch) { take(batch->found, batch->first + batch->ends.size() - 1); };
    threads = std::clamp(threads, 1, std::max(1, tbb::info::default_concurrency()));
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_pipeline(static_cast<std::size_t>(2 * threads),
                               tbb::make_filter<void, std::shared_ptr<Batch>>(tbb::filter_mode::serial_in_order, read) &
                                   tbb::make_filter<std::shared_ptr<Batch>, std::shared_ptr<Batch>>(tbb::filter_mode::parallel, run) &
                                   tbb::make_filter<std::shared_ptr<Batch>, void>(tbb::filter_mode::serial_in_order, use));
    });
}

/// What a batch of the bucket pass found: for each leaf its features cut to it, framed as its
/// bucket's records (tiling::put_tile_feature), with their count and engine vertices.
struct BucketEntries {
    struct Block {
        std::size_t leaf = 0;
        std::string records;
        std::size_t features = 0;
        std::size_t vertices = 0;
    };
    std::vector<Block> blocks;       ///< in the order the leaves first met in the batch
    std::vector<std::size_t> leaves; ///< scratch: one feature's
    tiling::TileFeature cut;         ///< scratch: one feature cut to one leaf
    std::string record;              ///< scratch: its record

    Block& block(std::size_t leaf)
    {
        // A batch is a run of input features: mostly near each other, so in few leaves.
        for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) {
            if (it->leaf == leaf) {
                return *it;
            }
        }
        Block& b = blocks.emplace_back();
        b.leaf = leaf;
        return b;
    }
};

/// What a batch of the reach pass found: the leaves whose reach grows, each with what it grows by.
struct ReachGrowth {
    std::vector<std::pair<std::size_t, Box>> grown;
    std::vector<std::size_t> leaves; ///< scratch: one feature's
};

class BucketMaker {
public:
    BucketMaker(tiling::WorkStore& store, const SpoolMeta& meta, const TilingOptions& tiling, const BucketOptions& options,
                const PassProgress& progress)
        : m_store(store), m_meta(meta), m_tiling(tiling), m_options(options), m_progress(progress)
    {
    }
    TileLayout run(tiling::PlanInput sample);

private:
    void reach_pass();
    void bucket_pass();
    void split_oversize();
    void split(std::size_t leaf, std::deque<std::size_t>& queue);
    void fill_child(std::size_t leaf, const std::vector<tiling::TileFeature>& parent);

    tiling::WorkStore& m_store;
    const SpoolMeta& m_meta;
    const TilingOptions& m_tiling;
    const BucketOptions& m_options;
    const PassProgress& m_progress;
    TileLayout m_layout;
};

void BucketMaker::reach_pass()
{
    const tiling::TilePlan& plan = m_layout.plan;
    const double h = m_layout.halo;
    std::vector<Box> r0(plan.size());
    for (std::size_t leaf = 0; leaf < plan.size(); ++leaf) {
        r0[leaf] = m_layout.has_data(leaf) ? m_layout.core_box(leaf).expanded(h) : Box{};
    }
    m_layout.reach = r0;
    // A reach is r0 and the points of the edges meeting it: a union, the same in any order.
    spool_pass<ReachGrowth>(
        m_store, m_options.threads, m_options.batch_bytes,
        [&](std::uint64_t, const detail::CleanFeature& cf, bool, ReachGrowth& found) {
            const Box b = box_of(cf);
            if (cf.rejected || b.empty()) {
                return;
            }
            found.leaves.clear(); // query() appends
            plan.query(b.expanded(h), found.leaves);
            for (std::size_t leaf : found.leaves) {
                if (!r0[leaf].empty()) {
                    Box grown;
                    grow_reach(cf, b, r0[leaf], grown);
                    if (!grown.empty()) {
                        found.grown.emplace_back(leaf, grown);
                    }
                }
            }
        },
        [&](const ReachGrowth& found, std::uint64_t last) {
            for (const auto& [leaf, grown] : found.grown) {
                m_layout.reach[leaf].add(grown);
            }
            if (m_progress) {
                m_progress(last + 1, 2 * m_meta.spooled);
            }
        });
    for (Box& r : m_layout.reach) {
        if (!r.empty()) {
            r = r.expanded(h);
        }
    }
}

void BucketMaker::bucket_pass()
{
    const std::size_t n = m_layout.plan.size();
    m_layout.bucket_vertices.assign(n, 0);
    m_layout.bucket_features.assign(n, 0);
    const ReachGrid grid(m_layout.reach, m_meta.sample.extent);
    std::vector<std::unique_ptr<tiling::TileCutter>> cutters(n);
    for (std::size_t leaf = 0; leaf < n; ++leaf) {
        if (!m_layout.reach[leaf].empty()) { // the grid finds no other
            cutters[leaf] = leaf_cutter(m_layout, m_meta, leaf);
        }
    }
    BucketWriter writer(m_store, m_options.buffer_bytes);
    // A plan's only leaf keeps no bucket file (read_bucket() makes it from features.bin): here
    // its features are only counted. The layer is then not held twice (40 MB of Andorra x43's
    // 127 in memory, or as much disk).
    const bool whole = whole_spool_bucket(m_layout);
    spool_pass<BucketEntries>(
        m_store, m_options.threads, m_options.batch_bytes,
        [&](std::uint64_t rank, const detail::CleanFeature& cf, bool has_z, BucketEntries& found) {
            const Box b = box_of(cf);
            if (cf.rejected || b.empty()) {
                return;
            }
            grid.query(b, found.leaves);
            for (std::size_t leaf : found.leaves) {
                if (!bucket_entry(*cutters[leaf], m_meta, cf, has_z, rank, found.cut)) {
                    continue;
                }
                BucketEntries::Block& block = found.block(leaf);
                ++block.features;
                block.vertices += tiling::engine_vertices(found.cut.feature.geometry);
                if (!whole) {
                    found.record.clear();
                    tiling::ByteWriter w(found.record);
                    tiling::put_tile_feature(w, found.cut);
                    frame_record(block.records, found.record);
                }
            }
        },
        [&](const BucketEntries& found, std::uint64_t last) {
            for (const BucketEntries::Block& block : found.blocks) {
                m_layout.bucket_vertices[block.leaf] += block.vertices;
                m_layout.bucket_features[block.leaf] += block.features;
                writer.add_framed(block.leaf, block.records);
            }
            if (m_progress) {
                m_progress(m_meta.spooled + last + 1, 2 * m_meta.spooled);
            }
        });
    writer.flush();
}

void BucketMaker::fill_child(std::size_t leaf, const std::vector<tiling::TileFeature>& parent)
{
    const Box R = reach_box(m_layout.core_box(leaf), m_layout.halo, parent);
    m_layout.reach[leaf] = R;
    m_layout.bucket_vertices[leaf] = 0;
    m_layout.bucket_features[leaf] = 0;
    const tiling::TileCutter cutter(R, tiling::detour_frame(m_meta.sample.extent, R));
    m_store.remove(files::bucket(leaf));
    BucketWriter writer(m_store, m_options.buffer_bytes);
    tiling::TileFeature child;
    for (const tiling::TileFeature& f : parent) {
        if (!cutter.cut(as_clean(f.feature), f.feature.geometry.has_z, child.feature, child.intact)) {
            continue;
        }
        child.rank = f.rank;
        child.feature.id = f.feature.id;
        child.intact = child.intact && f.intact;
        m_layout.bucket_vertices[leaf] += tiling::engine_vertices(child.feature.geometry);
        ++m_layout.bucket_features[leaf];
        writer.add(leaf, child);
    }
    writer.flush();
}

// The median of the bucket's vertices inside the core, on the core's longer side (the other
// side when every vertex has one coordinate there).
void BucketMaker::split(std::size_t leaf, std::deque<std::size_t>& queue)
{
    const std::vector<tiling::TileFeature> parent = read_bucket(m_store, m_layout, m_meta, leaf);
    const Box core = m_layout.core_box(leaf);
    const Region& region = m_layout.plan.core(leaf);
    std::vector<double> xs;
    std::vector<double> ys;
    for (const tiling::TileFeature& f : parent) {
        const detail::CleanFeature cf = as_clean(f.feature);
        for_each_edge(cf, [&](const Coord& p, const Coord&) {
            if (region.contains(p.x, p.y)) {
                xs.push_back(p.x);
                ys.push_back(p.y);
            }
        });
    }
    const int first = core.width() >= core.height() ? 0 : 1;
    for (int axis : {first, 1 - first}) {
        std::vector<double>& v = axis == 0 ? xs : ys;
        if (v.size() < 2 || (axis == 0 ? core.width() : core.height()) < 2 * m_layout.halo) {
            continue;
        }
        std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
        const double value = v[v.size() / 2];
        if (!(value > (axis == 0 ? core.xmin : core.ymin))) {
            continue;
        }
        const std::size_t upper = m_layout.plan.split_leaf(leaf, axis, value);
        m_layout.reach.resize(upper + 1);
        m_layout.bucket_vertices.resize(upper + 1, 0);
        m_layout.bucket_features.resize(upper + 1, 0);
        for (std::size_t child : {leaf, upper}) {
            fill_child(child, parent);
            if (m_layout.bucket_vertices[child] > m_options.max_tile_vertices) {
                queue.push_back(child);
            }
        }
        return;
    }
    std::int64_t largest_id = 0;
    std::size_t largest = 0;
    for (const tiling::TileFeature& f : parent) {
        if (const std::size_t n = tiling::engine_vertices(f.feature.geometry); n > largest) {
            largest = n;
            largest_id = f.feature.id;
        }
    }
    throw budget_error("tile " + std::to_string(leaf) + " cannot be split further and needs " +
                           std::to_string(m_layout.bucket_vertices[leaf]) + " vertices in one triangulation (its largest feature, id " +
                           std::to_string(largest_id) + ", has " + std::to_string(largest) + " there)",
                       m_layout.bucket_vertices[leaf]);
}

void BucketMaker::split_oversize()
{
    if (m_options.max_tile_vertices == 0) {
        return;
    }
    std::deque<std::size_t> queue;
    for (std::size_t leaf = 0; leaf < m_layout.plan.size(); ++leaf) {
        if (m_layout.bucket_vertices[leaf] > m_options.max_tile_vertices) {
            queue.push_back(leaf);
        }
    }
    if (!queue.empty() && m_tiling.plan.single) {
        const std::uint64_t n = m_layout.bucket_vertices[queue.front()];
        throw budget_error("--no-tiles snaps the whole layer in one triangulation of " + std::to_string(n) + " vertices", n);
    }
    while (!queue.empty()) {
        const std::size_t leaf = queue.front();
        queue.pop_front();
        split(leaf, queue);
    }
}

TileLayout BucketMaker::run(tiling::PlanInput sample)
{
    m_layout.plan = tiling::make_plan(std::move(sample), m_tiling.plan);
    m_layout.halo = m_options.halo;
    m_layout.seam_band = m_options.seam_band;
    m_store.remove_all("bucket-");
    reach_pass();
    bucket_pass();
    split_oversize();
    m_layout.plan.set_leaf_vertices(std::vector<std::size_t>(m_layout.bucket_vertices.begin(), m_layout.bucket_vertices.end()));
    std::string bytes;
    tiling::ByteWriter w(bytes);
    m_layout.save(w);
    m_store.put(files::layout, bytes);
    return m_layout;
}

} // namespace

TileLayout make_buckets(tiling::WorkStore& store, const SpoolMeta& meta, tiling::PlanInput sample,
                        const TilingOptions& tiling, const BucketOptions& options, const PassProgress& progress)
{
    return BucketMaker(store, meta, tiling, options, progress).run(std::move(sample));
}

} // namespace trisnap::stitch
