// make_buckets(): the tile plan, each leaf's reach box, each leaf's bucket (see spool.hpp).
#include "stitch/spool.hpp"

#include "tiling/records.hpp"
#include "tiling/tile_input.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <thread>

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
// meets a feature's box, without looking at every leaf. Read only once made; each thread asks
// through a Query of its own (the marks of the leaves it found).
class ReachGrid {
public:
    ReachGrid(const std::vector<Box>& reach, const Box& extent);

    class Query {
    public:
        explicit Query(const ReachGrid& grid) : m_grid(grid), m_stamp(grid.m_reach.size(), 0) {}
        /// The leaves whose reach box meets `b`, in leaf order.
        void run(const Box& b, std::vector<std::size_t>& out);

    private:
        const ReachGrid& m_grid;
        std::vector<std::uint32_t> m_stamp;
        std::uint32_t m_now = 0;
    };

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

void ReachGrid::Query::run(const Box& b, std::vector<std::size_t>& out)
{
    const ReachGrid& g = m_grid;
    out.clear();
    ++m_now;
    for (long x = g.cell(b.xmin, g.m_extent.xmin, g.m_nx); x <= g.cell(b.xmax, g.m_extent.xmin, g.m_nx); ++x) {
        for (long y = g.cell(b.ymin, g.m_extent.ymin, g.m_ny); y <= g.cell(b.ymax, g.m_extent.ymin, g.m_ny); ++y) {
            for (std::uint32_t k : g.m_cells[static_cast<std::size_t>(x * g.m_ny + y)]) {
                if (m_stamp[k] != m_now && g.m_reach[k].intersects(b)) {
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
    using Name = std::string (*)(std::size_t);
    /// `name`: the file a leaf's records go to (files::bucket, or files::bucket_tail for a
    /// second part of the features).
    BucketWriter(tiling::WorkStore& store, std::size_t cap, Name name = &files::bucket) : m_store(store), m_cap(cap), m_name(name) {}
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
                m_store.append(m_name(leaf), m_buffers[leaf]);
                m_buffers[leaf].clear();
                m_buffers[leaf].shrink_to_fit();
            }
        }
        m_buffered = 0;
    }

private:
    tiling::WorkStore& m_store;
    std::size_t m_cap;
    Name m_name;
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
    std::string record;
    for (const std::string& name : {files::bucket(leaf), files::bucket_tail(leaf)}) {
        if (!store.exists(name)) {
            continue; // a leaf no feature of that part reaches
        }
        const std::unique_ptr<tiling::InFile> file = store.open(name);
        tiling::RecordReader reader(*file);
        while (reader.next(record)) {
            tiling::ByteReader r(record, "bucket");
            out.push_back(tiling::get_tile_feature(r));
        }
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
    /// A part of the spooled features: ranks from `first` on, features.bin's bytes [begin, end).
    struct Part {
        std::uint64_t first = 0;
        std::uint64_t begin = 0;
        std::uint64_t end = 0;
    };
    /// Called after each feature of a part with the pass's base for the progress (0 for the
    /// first pass, the features' count for the second).
    using Tick = std::function<void(std::uint64_t)>;
    void split_parts();
    template <class F>
    void in_parts(F&& pass);
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
    std::vector<Part> m_parts;
};

// Two parts where there are two threads and features.bin holds BucketOptions::least_part_bytes
// for each: a part is cut at a record near the middle of the bytes (features.idx gives where each
// record starts). Below that the second thread cost more than it saved on the team's VM: Jakarta's
// buildings (~6 MB) and Natural Earth land (~7 MB, 66 % in one feature) kept their spool's wall
// time (0.017 and 0.042 s, 7 runs) for 0.01 and 0.025 CPU-s more; Andorra x43 (~40 MB) went
// 0.131 -> 0.111 s, 1 M polygons out of core 0.43 -> 0.33 s (bench/results/REPORT.md).
void BucketMaker::split_parts()
{
    const std::uint64_t least = std::max<std::uint64_t>(m_options.least_part_bytes, 1);
    const std::uint64_t bytes = m_store.size(files::features);
    m_parts = {Part{0, 0, bytes}};
    if (m_options.threads < 2 || bytes / 2 < least || !m_store.exists(files::offsets)) {
        return;
    }
    const std::unique_ptr<tiling::InFile> idx = m_store.open(files::offsets);
    const std::uint64_t count = idx->size() / sizeof(std::uint64_t);
    const auto offset = [&](std::uint64_t rank) {
        std::uint64_t o = 0;
        idx->read_at(rank * sizeof o, reinterpret_cast<char*>(&o), sizeof o);
        return o;
    };
    // The first record starting at or after the middle byte.
    std::uint64_t lo = 0;
    std::uint64_t hi = count;
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (offset(mid) < bytes / 2) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    if (lo == 0 || lo == count) {
        return;
    }
    const std::uint64_t cut = offset(lo);
    if (cut < least || bytes - cut < least) {
        return; // one record holds most of the layer
    }
    m_parts = {Part{0, 0, cut}, Part{lo, cut, bytes}};
}

// Runs `pass(k, features of part k, tick)` for each part, the first on this thread and the
// second on a thread of its own, and returns when both have ended. Only this thread reports
// progress (the run's progress checks for signals and may throw): with both parts' features
// done. When one part throws, the other stops at its next 4096th feature and the first error
// is thrown here.
template <class F>
void BucketMaker::in_parts(F&& pass)
{
    struct Stopped {};
    std::atomic<std::uint64_t> others{0}; // features the second part has done (as of its last 4096th)
    std::atomic<bool> stop{false};
    const auto run = [&](std::size_t k) {
        SpooledFeatures in(m_store, m_parts[k].begin, m_parts[k].end);
        std::uint64_t done = 0;
        const Tick tick = [&](std::uint64_t base) {
            if (done++ % 4096 != 0) { // after its first feature, and every 4096th after
                return;
            }
            if (stop.load(std::memory_order_relaxed)) {
                throw Stopped{};
            }
            if (k > 0) {
                others.store(done, std::memory_order_relaxed);
            } else if (m_progress) {
                m_progress(base + done + others.load(std::memory_order_relaxed), 2 * m_meta.spooled);
            }
        };
        pass(k, in, tick);
    };
    if (m_parts.size() == 1) {
        run(0);
        return;
    }
    std::exception_ptr error; // the second part's
    std::thread second([&] {
        try {
            run(1);
        } catch (const Stopped&) {
        } catch (...) {
            error = std::current_exception();
            stop = true;
        }
    });
    try {
        run(0);
    } catch (const Stopped&) {
        // the second part failed: its error is thrown below
    } catch (...) {
        stop = true;
        second.join();
        throw;
    }
    second.join();
    if (error) {
        std::rethrow_exception(error);
    }
}

void BucketMaker::reach_pass()
{
    const tiling::TilePlan& plan = m_layout.plan;
    const double h = m_layout.halo;
    std::vector<Box> r0(plan.size());
    for (std::size_t leaf = 0; leaf < plan.size(); ++leaf) {
        r0[leaf] = m_layout.has_data(leaf) ? m_layout.core_box(leaf).expanded(h) : Box{};
    }
    // Each part grows its own boxes from r0; a box is the union of the parts' (min and max:
    // the same doubles in any order).
    std::vector<std::vector<Box>> reach(m_parts.size(), r0);
    in_parts([&](std::size_t k, SpooledFeatures& in, const Tick& tick) {
        detail::CleanFeature cf;
        bool has_z = false;
        std::vector<std::size_t> leaves;
        while (in.next(cf, has_z)) {
            const Box b = box_of(cf);
            if (!cf.rejected && !b.empty()) {
                leaves.clear();
                plan.query(b.expanded(h), leaves);
                for (std::size_t leaf : leaves) {
                    if (!r0[leaf].empty()) {
                        grow_reach(cf, b, r0[leaf], reach[k][leaf]);
                    }
                }
            }
            tick(0);
        }
    });
    m_layout.reach = std::move(reach[0]);
    for (std::size_t k = 1; k < reach.size(); ++k) {
        for (std::size_t leaf = 0; leaf < plan.size(); ++leaf) {
            m_layout.reach[leaf].add(reach[k][leaf]);
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
    const ReachGrid grid(m_layout.reach, m_meta.sample.extent);
    // A plan's only leaf keeps no bucket file (read_bucket() makes it from features.bin): here
    // its features are only counted. The layer is then not held twice (40 MB of Andorra x43's
    // 127 in memory, or as much disk).
    const bool whole = whole_spool_bucket(m_layout);
    // Each part counts apart and writes its own files: the first part's records go to
    // files::bucket, the second's to files::bucket_tail, read after them (read_bucket()): each
    // bucket holds its features in input order, as one pass would have written it.
    std::vector<std::vector<std::uint64_t>> vertices(m_parts.size(), std::vector<std::uint64_t>(n, 0));
    std::vector<std::vector<std::uint64_t>> features(m_parts.size(), std::vector<std::uint64_t>(n, 0));
    const std::size_t buffer = std::max<std::size_t>(m_options.buffer_bytes / m_parts.size(), 1);
    in_parts([&](std::size_t k, SpooledFeatures& in, const Tick& tick) {
        ReachGrid::Query query(grid);
        std::vector<std::unique_ptr<tiling::TileCutter>> cutters(n);
        BucketWriter writer(m_store, buffer, k == 0 ? &files::bucket : &files::bucket_tail);
        detail::CleanFeature cf;
        bool has_z = false;
        std::vector<std::size_t> leaves;
        tiling::TileFeature tf;
        for (std::uint64_t rank = m_parts[k].first; in.next(cf, has_z); ++rank) {
            const Box b = box_of(cf);
            if (!cf.rejected && !b.empty()) {
                query.run(b, leaves);
                for (std::size_t leaf : leaves) {
                    if (!cutters[leaf]) {
                        cutters[leaf] = leaf_cutter(m_layout, m_meta, leaf);
                    }
                    if (!bucket_entry(*cutters[leaf], m_meta, cf, has_z, rank, tf)) {
                        continue;
                    }
                    vertices[k][leaf] += tiling::engine_vertices(tf.feature.geometry);
                    ++features[k][leaf];
                    if (!whole) {
                        writer.add(leaf, tf);
                    }
                }
            }
            tick(m_meta.spooled);
        }
        writer.flush();
    });
    m_layout.bucket_vertices.assign(n, 0);
    m_layout.bucket_features.assign(n, 0);
    for (std::size_t k = 0; k < m_parts.size(); ++k) {
        for (std::size_t leaf = 0; leaf < n; ++leaf) {
            m_layout.bucket_vertices[leaf] += vertices[k][leaf];
            m_layout.bucket_features[leaf] += features[k][leaf];
        }
    }
}

void BucketMaker::fill_child(std::size_t leaf, const std::vector<tiling::TileFeature>& parent)
{
    const Box R = reach_box(m_layout.core_box(leaf), m_layout.halo, parent);
    m_layout.reach[leaf] = R;
    m_layout.bucket_vertices[leaf] = 0;
    m_layout.bucket_features[leaf] = 0;
    const tiling::TileCutter cutter(R, tiling::detour_frame(m_meta.sample.extent, R));
    m_store.remove(files::bucket(leaf));
    m_store.remove(files::bucket_tail(leaf));
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
    split_parts();
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
