// make_buckets(): the tile plan, each leaf's reach box, each leaf's bucket (see spool.hpp).
#include "stitch/spool.hpp"

#include "tiling/records.hpp"
#include "tiling/tile_input.hpp"

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
    void query(const Box& b, std::vector<std::size_t>& out);

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
    std::vector<std::uint32_t> m_stamp;
    std::uint32_t m_now = 0;
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
    m_stamp.assign(reach.size(), 0);
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

void ReachGrid::query(const Box& b, std::vector<std::size_t>& out)
{
    out.clear();
    ++m_now;
    for (long x = cell(b.xmin, m_extent.xmin, m_nx); x <= cell(b.xmax, m_extent.xmin, m_nx); ++x) {
        for (long y = cell(b.ymin, m_extent.ymin, m_ny); y <= cell(b.ymax, m_extent.ymin, m_ny); ++y) {
            for (std::uint32_t k : m_cells[static_cast<std::size_t>(x * m_ny + y)]) {
                if (m_stamp[k] != m_now && m_reach[k].intersects(b)) {
                    m_stamp[k] = m_now;
                    out.push_back(k);
                }
            }
        }
    }
    std::sort(out.begin(), out.end());
}

// Bucket records buffered per leaf and appended to the store in large blocks.
class BucketWriter {
public:
    BucketWriter(tiling::WorkStore& store, std::size_t cap) : m_store(store), m_cap(cap) {}
    void add(std::size_t leaf, const tiling::TileFeature& f)
    {
        if (m_buffers.size() <= leaf) {
            m_buffers.resize(leaf + 1);
        }
        std::string& b = m_buffers[leaf];
        const std::size_t start = b.size();
        b.append(sizeof(std::uint32_t), '\0');
        tiling::ByteWriter w(b);
        tiling::put_tile_feature(w, f);
        const auto n = static_cast<std::uint32_t>(b.size() - start - sizeof(std::uint32_t));
        std::memcpy(b.data() + start, &n, sizeof n);
        m_buffered += b.size() - start;
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
    std::size_t m_cap;
    std::vector<std::string> m_buffers;
    std::size_t m_buffered = 0;
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
    SpooledFeatures in(m_store);
    detail::CleanFeature cf;
    bool has_z = false;
    std::vector<std::size_t> leaves;
    for (std::uint64_t rank = 0; in.next(cf, has_z); ++rank) {
        const Box b = box_of(cf);
        if (!cf.rejected && !b.empty()) {
            leaves.clear();
            plan.query(b.expanded(h), leaves);
            for (std::size_t leaf : leaves) {
                if (!r0[leaf].empty()) {
                    grow_reach(cf, b, r0[leaf], m_layout.reach[leaf]);
                }
            }
        }
        if (m_progress && rank % 4096 == 0) {
            m_progress(rank, 2 * m_meta.spooled);
        }
    }
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
    ReachGrid grid(m_layout.reach, m_meta.sample.extent);
    std::vector<std::unique_ptr<tiling::TileCutter>> cutters(n);
    BucketWriter writer(m_store, m_options.buffer_bytes);
    // A plan's only leaf keeps no bucket file (read_bucket() makes it from features.bin): here
    // its features are only counted. The layer is then not held twice (40 MB of Andorra x43's
    // 127 in memory, or as much disk).
    const bool whole = whole_spool_bucket(m_layout);
    SpooledFeatures in(m_store);
    detail::CleanFeature cf;
    bool has_z = false;
    std::vector<std::size_t> leaves;
    tiling::TileFeature tf;
    for (std::uint64_t rank = 0; in.next(cf, has_z); ++rank) {
        const Box b = box_of(cf);
        if (!cf.rejected && !b.empty()) {
            grid.query(b, leaves);
            for (std::size_t leaf : leaves) {
                if (!cutters[leaf]) {
                    cutters[leaf] = leaf_cutter(m_layout, m_meta, leaf);
                }
                if (!bucket_entry(*cutters[leaf], m_meta, cf, has_z, rank, tf)) {
                    continue;
                }
                m_layout.bucket_vertices[leaf] += tiling::engine_vertices(tf.feature.geometry);
                ++m_layout.bucket_features[leaf];
                if (!whole) {
                    writer.add(leaf, tf);
                }
            }
        }
        if (m_progress && rank % 4096 == 0) {
            m_progress(m_meta.spooled + rank, 2 * m_meta.spooled);
        }
    }
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
    tiling::PlanOptions plan = m_tiling.plan;
    // No cut that only copies a band of halo into both halves, unless a memory limit needs the
    // tiles within their vertex budget (split_oversize() then splits what still does not fit).
    const bool unlimited = m_options.max_tile_vertices == 0;
    plan.halo = unlimited ? m_options.halo : 0.0;
    tiling::PlanInput whole; // what a plan of one tile needs: the extent and the count
    whole.extent = sample.extent;
    whole.vertices = sample.vertices;
    m_layout.plan = tiling::make_plan(std::move(sample), plan);
    m_layout.halo = m_options.halo;
    m_layout.seam_band = m_options.seam_band;
    m_store.remove_all("bucket-");
    reach_pass();
    bucket_pass();
    // A tile's box grows to hold both ends of every edge meeting it. When that makes one tile
    // hold more than 3/4 of the layer anyway, the other tiles only snap copies again: NJ shore
    // (one polygon, a few straight edges along the sea) put 211 k of its 254 k vertices in one
    // of 5-8 tiles holding 553-846 k, and ran 1.8-3.2x the untiled CPU at 1e-5 to 3e-3 degrees,
    // slower in wall time than one untiled thread even on two. The balanced plan, without a
    // memory limit, is then one tile (a limit needs tiles within their budget; a --tile-size
    // grid is the user's choice).
    const std::uint64_t largest = m_layout.bucket_vertices.empty()
                                      ? 0
                                      : *std::max_element(m_layout.bucket_vertices.begin(), m_layout.bucket_vertices.end());
    if (unlimited && !plan.single && !(plan.tile_size > 0) && m_layout.plan.size() > 1 && largest > m_meta.vertices / 4 * 3) {
        plan.single = true;
        m_layout.plan = tiling::make_plan(std::move(whole), plan);
        m_store.remove_all("bucket-");
        reach_pass();
        bucket_pass();
    }
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
