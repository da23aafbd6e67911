// The work directory (its records: test_records.cpp): files appear only when committed, damaged
// files are refused; the vertex sample does not depend on input order; a plan survives
// save/load and leaf splits; a tiled run on a directory store with a small memory pool (tiles
// split to fit) and interrupted between tiles gives the untiled output.
#include "generators.hpp"
#include "spool_input.hpp"
#include "tiled_check.hpp"

#include "stitch/spool.hpp"
#include "stitch/tiled_snap.hpp"
#include "tiling/records.hpp"
#include "tiling/sample.hpp"
#include "tiling/tile_input.hpp"
#include "tiling/work_store.hpp"
#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>

#include <unistd.h>

namespace trisnap {
namespace {

namespace fs = std::filesystem;

/// A coverage of n x n squares, a line of two parts (FID 1000) and, fourth, a feature the
/// cleaning rejects (FID 1001, a NaN: problem 106, nothing spooled to snap).
std::vector<Feature> coverage_line_and_rejected(int n, unsigned seed)
{
    std::vector<Feature> input = perturbed_grid_coverage(n, n, 1.0, 0.2, seed, 1, 0.004);
    Feature line;
    line.id = 1000;
    line.geometry.type = Geometry::Type::MultiLineString;
    line.geometry.lines = {{{0.5, -1}, {3.5, 2.25}, {6.5, 9.5}}, {{1, 1}, {2, 1.5}}};
    input.push_back(line);
    Feature rejected = input.front();
    rejected.id = 1001;
    rejected.geometry.polygons[0].rings[0][1].x = std::nan("");
    input.insert(input.begin() + 3, rejected);
    return input;
}

/// Every feature of the run's stitched output is the untiled run's, and there are `count`.
void expect_untiled_output(stitch::TiledRun& run, const SnapResult& untiled, std::size_t count)
{
    const auto merger = run.output();
    stitch::OutputItem item;
    std::size_t n = 0;
    while (merger->next(item)) {
        const FeatureOutput& expected = untiled.features[item.seq];
        ASSERT_EQ(expected.id, item.output.id);
        EXPECT_EQ(to_wkt(expected.geometry), to_wkt(item.output.geometry)) << "feature " << expected.id;
        ++n;
    }
    EXPECT_EQ(n, count);
}

class StoreTest : public ::testing::TestWithParam<bool> {
protected:
    std::unique_ptr<tiling::WorkStore> make()
    {
        if (!GetParam()) {
            return tiling::make_memory_store();
        }
        // A parameterised test's name holds a '/': one directory level, so that remove_all(m_dir)
        // leaves nothing behind in the temporary directory.
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');
        m_dir = fs::temp_directory_path() / ("trisnap-store-" + std::to_string(::getpid()) + "-" + name);
        fs::remove_all(m_dir);
        return tiling::make_directory_store(m_dir.string());
    }
    void TearDown() override
    {
        if (!m_dir.empty()) {
            fs::remove_all(m_dir);
        }
    }
    fs::path m_dir;
};

TEST_P(StoreTest, FilesAppearOnlyWhenCommitted)
{
    auto store = make();
    {
        auto f = store->create("a");
        f->write("hello");
        EXPECT_FALSE(store->exists("a"));
    } // dropped without commit: nothing, not even a temporary file
    EXPECT_FALSE(store->exists("a"));
    if (GetParam()) {
        EXPECT_TRUE(fs::is_empty(m_dir));
    }
    store->put("a", "first");
    store->put("a", "second"); // replaces
    EXPECT_EQ(store->get("a"), "second");
    store->append("b", "x");
    store->append("b", "yz");
    EXPECT_EQ(store->get("b"), "xyz");
    EXPECT_EQ(store->size("b"), 3u);
    store->remove_all("b");
    EXPECT_FALSE(store->exists("b"));
    EXPECT_THROW(store->open("missing"), tiling::work_error);
}

// A file appended to while it is open: the reader keeps what it opened (in memory the two share
// the chunks written before, and the appends go past the reader's end; on disk its size() and
// bytes up to it), a new open sees it all.
// Pieces of odd sizes, so that they straddle the memory store's chunks (256 bytes up to 1 MiB).
TEST_P(StoreTest, AppendsWhileAFileIsOpenLeaveItsReaderWhatItOpened)
{
    auto store = make();
    std::string all;
    const auto add = [&](int from, int to) {
        for (int i = from; i < to; ++i) {
            const std::string piece(static_cast<std::size_t>(1 + (i * 7919) % 3001), static_cast<char>('a' + i % 26));
            store->append("b", piece);
            all += piece;
        }
    };
    add(0, 500);
    const std::string first = all;
    auto reader = store->open("b");
    add(500, 1000);
    ASSERT_EQ(reader->size(), first.size());
    std::string got(first.size(), '\0');
    std::size_t n = 0;
    while (n < got.size()) {
        const std::size_t k = reader->read(got.data() + n, std::min<std::size_t>(4093, got.size() - n));
        ASSERT_GT(k, 0u);
        n += k;
    }
    EXPECT_EQ(got, first);
    if (!GetParam()) { // in memory (on disk the open file is the file, and reads on past its old end)
        char past = 0;
        EXPECT_EQ(reader->read(&past, 1), 0u) << "the reader ends where it opened the file";
    }
    EXPECT_EQ(store->get("b"), all);
    std::string middle(5000, '\0');
    store->open("b")->read_at(first.size() - 2500, middle.data(), middle.size());
    EXPECT_EQ(middle, all.substr(first.size() - 2500, 5000));
}

TEST_P(StoreTest, RecordsStreamAndSeekAndRefuseTruncation)
{
    auto store = make();
    std::vector<std::uint64_t> offsets;
    {
        auto f = store->create("r");
        tiling::RecordWriter w(*f);
        for (int i = 0; i < 1000; ++i) {
            offsets.push_back(w.write(std::string(static_cast<std::size_t>(i % 37), static_cast<char>('a' + i % 26))));
        }
        f->commit();
    }
    auto in = store->open("r");
    tiling::RecordReader reader(*in, 64); // a small buffer: records straddle refills
    std::string record;
    int n = 0;
    while (reader.next(record)) {
        ASSERT_EQ(record, std::string(static_cast<std::size_t>(n % 37), static_cast<char>('a' + n % 26)));
        ++n;
    }
    EXPECT_EQ(n, 1000);
    EXPECT_EQ(reader.at(offsets[500]), std::string(500 % 37, static_cast<char>('a' + 500 % 26)));
    const std::string whole = store->get("r");
    store->put("cut", whole.substr(0, whole.size() - 3));
    auto cut = store->open("cut");
    tiling::RecordReader cut_reader(*cut);
    EXPECT_THROW(
        {
            while (cut_reader.next(record)) {
            }
        },
        tiling::work_error);
}

// Records larger than the reader's buffer (a feature across a whole tile) are read into the
// record itself; the small ones around them still come through the buffer, and a large record
// cut short is refused like a small one.
TEST_P(StoreTest, RecordsLargerThanTheBufferReadWhole)
{
    auto store = make();
    const auto record_of = [](int i) {
        const std::size_t size = i % 5 == 2 ? static_cast<std::size_t>(1000 + 97 * i) : static_cast<std::size_t>(i % 41);
        std::string r(size, '\0');
        for (std::size_t k = 0; k < size; ++k) {
            r[k] = static_cast<char>('a' + (static_cast<std::size_t>(i) * 7 + k) % 26);
        }
        return r;
    };
    {
        auto f = store->create("r");
        tiling::RecordWriter w(*f);
        for (int i = 0; i < 60; ++i) {
            w.write(record_of(i));
        }
        f->commit();
    }
    for (const std::size_t buffer : {std::size_t{64}, std::size_t{999}, std::size_t{1 << 20}}) {
        auto in = store->open("r");
        tiling::RecordReader reader(*in, buffer);
        std::string record = "left over";
        int n = 0;
        while (reader.next(record)) {
            ASSERT_EQ(record, record_of(n)) << "record " << n << ", buffer " << buffer;
            ++n;
        }
        EXPECT_EQ(n, 60) << "buffer " << buffer;
    }
    const std::string whole = store->get("r");
    // Cut inside the last large record (i = 57: 6,529 bytes, the last bytes of the file but two
    // small records), then inside its first bytes past the length.
    const std::size_t tail = record_of(58).size() + record_of(59).size() + 8;
    for (const std::size_t cut_at : {whole.size() - tail - 100, whole.size() - tail - record_of(57).size() + 10}) {
        store->put("cut", whole.substr(0, cut_at));
        auto cut = store->open("cut");
        tiling::RecordReader cut_reader(*cut, 64);
        std::string record;
        int n = 0;
        EXPECT_THROW(
            {
                while (cut_reader.next(record)) {
                    ++n;
                }
            },
            tiling::work_error)
            << "cut at " << cut_at;
        EXPECT_EQ(n, 57) << "the records before the cut one read whole";
    }
}

// RecordReader sizes its reads by InFile::size() (so a small file does not fill a whole buffer),
// but only as a hint: a file whose size says less or more than it holds still reads whole.
class MisreportedSize : public tiling::InFile {
public:
    MisreportedSize(std::unique_ptr<tiling::InFile> file, std::uint64_t claimed) : m_file(std::move(file)), m_claimed(claimed) {}
    std::size_t read(char* out, std::size_t n) override { return m_file->read(out, n); }
    void read_at(std::uint64_t offset, char* out, std::size_t n) override { m_file->read_at(offset, out, n); }
    std::uint64_t size() const override { return m_claimed; }

private:
    std::unique_ptr<tiling::InFile> m_file;
    std::uint64_t m_claimed;
};

TEST(RecordReader, TheFileSizeIsOnlyAHint)
{
    auto store = tiling::make_memory_store();
    {
        auto f = store->create("r");
        tiling::RecordWriter w(*f);
        for (int i = 0; i < 300; ++i) {
            w.write(std::string(static_cast<std::size_t>(i % 53), static_cast<char>('a' + i % 26)));
        }
        f->commit();
    }
    const std::uint64_t size = store->open("r")->size();
    for (const std::uint64_t claimed : {std::uint64_t{0}, size / 3, size, 10 * size}) {
        MisreportedSize in(store->open("r"), claimed);
        tiling::RecordReader reader(in, 100);
        std::string record;
        int n = 0;
        while (reader.next(record)) {
            ASSERT_EQ(record, std::string(static_cast<std::size_t>(n % 53), static_cast<char>('a' + n % 26))) << claimed;
            ++n;
        }
        EXPECT_EQ(n, 300) << "size() claimed " << claimed << " of " << size << " bytes";
    }
}

// spool.meta holds the plan's sample in a store on disk (a resumed run or another process plans
// from it) and leaves it out in memory, where the caller has it and nothing reads it back; the
// rest of the meta is kept either way.
TEST_P(StoreTest, SpoolMetaKeepsThePlansSampleOnlyOnDisk)
{
    auto store = make();
    const auto input = perturbed_grid_coverage(12, 12, 1.0, 0.2, 3, 1, 0.004);
    stitch::SpoolMeta meta = spool_features(*store, input, 0.01, 100, 64);
    ASSERT_GT(meta.sample.level, 0) << "a sampled plan";
    ASSERT_FALSE(meta.sample.xs.empty());
    const std::string bytes = store->get(stitch::files::spool_meta);
    tiling::ByteReader r(bytes, "spool meta");
    const stitch::SpoolMeta loaded = stitch::SpoolMeta::load(r);
    EXPECT_TRUE(r.done());
    EXPECT_EQ(loaded.records, meta.records);
    EXPECT_EQ(loaded.spooled, meta.spooled);
    EXPECT_EQ(loaded.vertices, meta.vertices);
    EXPECT_EQ(loaded.sample.vertices, meta.sample.vertices);
    EXPECT_EQ(loaded.sample.level, meta.sample.level);
    EXPECT_EQ(loaded.sample.extent.xmin, meta.sample.extent.xmin);
    EXPECT_EQ(loaded.sample.extent.ymax, meta.sample.extent.ymax);
    EXPECT_EQ(loaded.largest_fid, meta.largest_fid);
    if (GetParam()) {
        EXPECT_EQ(loaded.sample.xs, meta.sample.xs);
        EXPECT_EQ(loaded.sample.ys, meta.sample.ys);
    } else {
        EXPECT_TRUE(loaded.sample.xs.empty());
        EXPECT_TRUE(loaded.sample.ys.empty());
    }
}

// The plan takes the sample's vertices from the meta (one copy of up to 256 MiB, not three): the
// meta keeps the extent and counts the tiles' cutting reads, and the plan is the median k-d tree
// of the sample, whatever the order of its vertices.
TEST_P(StoreTest, ThePlanTakesTheSampleAndDoesNotDependOnItsOrder)
{
    auto store = make();
    const auto input = perturbed_grid_coverage(12, 12, 1.0, 0.2, 3, 1, 0.004);
    stitch::SpoolMeta meta = spool_features(*store, input, 0.01, 400, 64);
    const tiling::PlanInput sample = meta.sample;
    ASSERT_GT(sample.xs.size(), 100u);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 60;
    stitch::TiledRun run(*store, options_at(0.01), tiling, stitch::ScheduleOptions{});
    run.plan(meta);
    EXPECT_TRUE(meta.sample.xs.empty() && meta.sample.ys.empty()) << "the sample's vertices were copied";
    EXPECT_EQ(meta.sample.vertices, sample.vertices);
    EXPECT_EQ(meta.sample.level, sample.level);
    EXPECT_EQ(meta.sample.extent.xmin, sample.extent.xmin);
    EXPECT_EQ(meta.sample.extent.ymax, sample.extent.ymax);
    const tiling::TilePlan& planned = run.layout().plan;
    ASSERT_GT(planned.size(), 4u);
    tiling::PlanInput shuffled = sample;
    std::vector<std::size_t> order(shuffled.xs.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        order[i] = i;
    }
    std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
    for (std::size_t i = 0; i < order.size(); ++i) {
        shuffled.xs[i] = sample.xs[order[i]];
        shuffled.ys[i] = sample.ys[order[i]];
    }
    tiling::PlanOptions as_run = tiling.plan;
    as_run.halo = run.layout().halo; // as make_buckets() plans without a memory limit
    for (const tiling::PlanInput& in : {sample, shuffled}) {
        const tiling::TilePlan again = tiling::make_plan(in, as_run);
        ASSERT_EQ(again.size(), planned.size());
        for (std::size_t k = 0; k < planned.size(); ++k) {
            EXPECT_EQ(again.core(k), planned.core(k)) << "leaf " << k;
        }
    }
    // Cut by count only, each leaf's core holds at most the budget (scaled to the sample) of the
    // sample's vertices; the run's plan (which leaves out cuts that only copy their halo band:
    // here median cuts along the coverage's densified edges) has no more leaves than that.
    const tiling::TilePlan by_count = tiling::make_plan(sample, tiling.plan);
    EXPECT_LE(planned.size(), by_count.size());
    const std::size_t budget = tiling.plan.vertex_budget >> sample.level;
    for (std::size_t k = 0; k < by_count.size(); ++k) {
        std::size_t inside = 0;
        for (std::size_t i = 0; i < sample.xs.size(); ++i) {
            inside += by_count.core(k).contains(sample.xs[i], sample.ys[i]) ? 1 : 0;
        }
        EXPECT_LE(inside, std::max<std::size_t>(budget, 1)) << "leaf " << k;
        EXPECT_GT(inside, 0u) << "leaf " << k;
    }
}

// The plan's reach and bucket passes: each leaf's reach is what reach_box() grows over every
// feature, and every bucket holds exactly what cutting each spooled feature to the leaf's reach
// one after the other gives (rank, id, whether whole, geometry), in rank order. (The passes run
// on one thread whatever --threads says: a version that cut on several was slower and reverted,
// REPORT.md "Sixteen bytes a vertex".)
TEST(Buckets, ReachesAndBucketsAreTheOneByOneCuts)
{
    const double t = 0.01;
    std::vector<Feature> input = perturbed_grid_coverage(20, 20, 1.0, 0.2, 3, 1, 0.004);
    for (Feature& f : coverage_line_and_rejected(8, 5)) {
        f.id += 100000; // lines and a rejected feature besides the coverage
        input.push_back(std::move(f));
    }
    struct Planned {
        std::unique_ptr<tiling::WorkStore> store;
        stitch::SpoolMeta meta;
        stitch::TileLayout layout;
    };
    Planned one;
    one.store = tiling::make_memory_store();
    one.meta = spool_features(*one.store, input, t, 400, 64);
    {
        stitch::TilingOptions tiling;
        tiling.plan.vertex_budget = 60;
        stitch::TiledRun run(*one.store, options_at(t), tiling, stitch::ScheduleOptions{});
        run.plan(one.meta);
        one.layout = run.layout();
    }
    const std::size_t leaves = one.layout.plan.size();
    ASSERT_GT(leaves, 8u);
    const auto same_box = [](const tiling::Box& a, const tiling::Box& b) {
        return a.xmin == b.xmin && a.ymin == b.ymin && a.xmax == b.xmax && a.ymax == b.ymax;
    };
    // Each leaf's reach as reach_box() grows it over every feature, one after the other.
    std::vector<tiling::TileFeature> whole;
    {
        const tiling::Box everywhere{-1e9, -1e9, 1e9, 1e9};
        const tiling::TileCutter uncut(everywhere, tiling::detour_frame(one.meta.sample.extent, everywhere));
        stitch::SpooledFeatures spooled(*one.store);
        detail::CleanFeature cf;
        bool has_z = false;
        while (spooled.next(cf, has_z)) {
            tiling::TileFeature tf;
            if (!cf.rejected && uncut.cut(cf, has_z, tf.feature, tf.intact)) {
                ASSERT_TRUE(tf.intact);
                whole.push_back(std::move(tf));
            }
        }
    }
    std::size_t grown = 0;
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
        if (!one.layout.has_data(leaf)) {
            EXPECT_TRUE(one.layout.reach[leaf].empty()) << "leaf " << leaf;
            continue;
        }
        const tiling::Box want = stitch::reach_box(one.layout.core_box(leaf), one.layout.halo, whole);
        const tiling::Box& got = one.layout.reach[leaf];
        EXPECT_TRUE(same_box(got, want)) << "leaf " << leaf;
        const tiling::Box r0 = one.layout.core_box(leaf).expanded(one.layout.halo).expanded(one.layout.halo);
        grown += r0.contains(got) ? 0 : 1;
    }
    EXPECT_GT(grown, 0u) << "some reach grew past the core and halo (features crossing it)";
    std::size_t entries = 0, cut = 0;
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
        const tiling::Box& r = one.layout.reach[leaf];
        const std::vector<tiling::TileFeature> a = stitch::read_bucket(*one.store, one.layout, one.meta, leaf);
        // What one thread cutting feature after feature gives.
        std::vector<tiling::TileFeature> expected;
        if (!r.empty()) {
            const tiling::TileCutter cutter(r, tiling::detour_frame(one.meta.sample.extent, r));
            stitch::SpooledFeatures spooled(*one.store);
            detail::CleanFeature cf;
            bool has_z = false;
            for (std::uint64_t rank = 0; spooled.next(cf, has_z); ++rank) {
                const tiling::Box box = stitch::box_of(cf);
                tiling::TileFeature tf;
                if (cf.rejected || box.empty() || !r.intersects(box) || !cutter.cut(cf, has_z, tf.feature, tf.intact)) {
                    continue;
                }
                tf.rank = rank;
                tf.feature.id = stitch::engine_id(one.meta, cf);
                expected.push_back(std::move(tf));
            }
        }
        ASSERT_EQ(a.size(), expected.size()) << "leaf " << leaf;
        EXPECT_EQ(one.layout.bucket_features[leaf], expected.size()) << "leaf " << leaf;
        for (std::size_t k = 0; k < expected.size(); ++k, ++entries) {
            EXPECT_EQ(a[k].rank, expected[k].rank) << "leaf " << leaf << " entry " << k;
            EXPECT_EQ(a[k].feature.id, expected[k].feature.id) << "leaf " << leaf << " entry " << k;
            EXPECT_EQ(a[k].intact, expected[k].intact) << "leaf " << leaf << " entry " << k;
            EXPECT_EQ(to_wkt(a[k].feature.geometry), to_wkt(expected[k].feature.geometry)) << "leaf " << leaf << " entry " << k;
            cut += expected[k].intact ? 0 : 1;
        }
    }
    EXPECT_GT(entries, input.size()) << "features in several buckets (halos)";
    EXPECT_GT(cut, 0u) << "some features cut to a reach";
}

// A plan of one leaf (as with --no-tiles) stores no bucket: its bucket is features.bin, each
// feature cut to the reach as it is read, and holds exactly what a bucket file would: every
// feature that is not rejected, in order, whole, with the counts the layout gives.
TEST_P(StoreTest, APlanOfOneLeafTakesItsBucketFromTheSpool)
{
    auto store = make();
    const double t = 0.01;
    const std::vector<Feature> input = coverage_line_and_rejected(8, 5);
    stitch::SpoolMeta meta = spool_features(*store, input, t);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 10000000;
    stitch::TiledRun run(*store, options_at(t), tiling, stitch::ScheduleOptions{});
    run.plan(meta);
    const stitch::TileLayout& layout = run.layout();
    ASSERT_EQ(layout.plan.size(), 1u);
    EXPECT_TRUE(stitch::whole_spool_bucket(layout));
    EXPECT_FALSE(store->exists(stitch::files::bucket(0))) << "the layer was stored twice";
    const std::vector<tiling::TileFeature> bucket = stitch::read_bucket(*store, layout, meta, 0);
    stitch::SpooledFeatures spooled(*store);
    detail::CleanFeature cf;
    bool has_z = false;
    std::size_t k = 0;
    std::uint64_t vertices = 0;
    for (std::uint64_t rank = 0; spooled.next(cf, has_z); ++rank) {
        if (cf.rejected) {
            continue;
        }
        ASSERT_LT(k, bucket.size()) << "feature " << cf.id << " is missing";
        const tiling::TileFeature& f = bucket[k++];
        EXPECT_EQ(f.rank, rank);
        EXPECT_EQ(f.feature.id, stitch::engine_id(meta, cf));
        EXPECT_TRUE(f.intact) << "feature " << cf.id << " was cut";
        const detail::CleanFeature back = stitch::as_clean(f.feature);
        ASSERT_EQ(back.rings.size(), cf.rings.size()) << "feature " << cf.id;
        for (std::size_t r = 0; r < cf.rings.size(); ++r) {
            EXPECT_EQ(back.rings[r].points, cf.rings[r].points) << "feature " << cf.id << " ring " << r;
        }
        EXPECT_EQ(back.lines, cf.lines) << "feature " << cf.id;
        vertices += tiling::engine_vertices(f.feature.geometry);
    }
    EXPECT_EQ(k, bucket.size());
    EXPECT_EQ(bucket.size(), input.size() - 1) << "only the rejected feature stays out";
    EXPECT_EQ(layout.bucket_features[0], bucket.size());
    EXPECT_EQ(layout.bucket_vertices[0], vertices);
}

// With two threads and a spool of twice BucketOptions::least_part_bytes (1 MiB here) the passes
// over the features run in two parts at once: the layout and the buckets are those of one pass (the same reach boxes and counts, each
// bucket's records the same bytes in the same order), the second part's records in the buckets'
// tails. A progress that throws (a signal) stops both parts and comes out of make_buckets().
TEST_P(StoreTest, TheSpoolsPassesInTwoPartsMakeTheBucketsOfOne)
{
    const double t = 0.01;
    std::vector<Feature> input = perturbed_grid_coverage(80, 80, 1.0, 0.2, 9, 8, 0.004);
    for (Feature& f : coverage_line_and_rejected(8, 5)) {
        f.id += 100000; // a line and a rejected feature besides the coverage
        input.push_back(std::move(f));
    }
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 20000;
    stitch::BucketOptions bo;
    bo.halo = 4 * t;
    bo.seam_band = 2 * t + 4e-9;
    bo.least_part_bytes = std::uint64_t{1} << 20;
    struct Made {
        std::unique_ptr<tiling::WorkStore> store;
        stitch::SpoolMeta meta;
        stitch::TileLayout layout;
    };
    const auto made = [&](std::unique_ptr<tiling::WorkStore> store, int threads, const stitch::PassProgress& progress = {}) {
        Made m{std::move(store), {}, {}};
        m.meta = spool_features(*m.store, input, t);
        bo.threads = threads;
        m.layout = stitch::make_buckets(*m.store, m.meta, m.meta.sample.take_vertices(), tiling, bo, progress);
        return m;
    };
    const Made one = made(tiling::make_memory_store(), 1);
    std::uint64_t reported = 0;
    const Made two = made(make(), 2, [&](std::uint64_t done, std::uint64_t) { reported = std::max(reported, done); });
    ASSERT_GT(two.store->size(stitch::files::features), std::uint64_t{2} << 20) << "a spool too small for two parts";
    const std::size_t leaves = one.layout.plan.size();
    ASSERT_GT(leaves, 8u);
    ASSERT_EQ(two.layout.plan.size(), leaves);
    EXPECT_GT(reported, two.meta.spooled) << "the progress did not count the second pass";
    EXPECT_LE(reported, 2 * two.meta.spooled);
    const auto records = [](const Made& m, std::size_t leaf) {
        std::vector<std::string> out;
        for (const tiling::TileFeature& f : stitch::read_bucket(*m.store, m.layout, m.meta, leaf)) {
            tiling::ByteWriter w(out.emplace_back());
            tiling::put_tile_feature(w, f);
        }
        return out;
    };
    std::size_t tails = 0;
    std::size_t entries = 0;
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
        const tiling::Box& a = one.layout.reach[leaf];
        const tiling::Box& b = two.layout.reach[leaf];
        EXPECT_TRUE(a.xmin == b.xmin && a.ymin == b.ymin && a.xmax == b.xmax && a.ymax == b.ymax) << "leaf " << leaf;
        EXPECT_EQ(one.layout.bucket_vertices[leaf], two.layout.bucket_vertices[leaf]) << "leaf " << leaf;
        EXPECT_EQ(one.layout.bucket_features[leaf], two.layout.bucket_features[leaf]) << "leaf " << leaf;
        EXPECT_FALSE(one.store->exists(stitch::files::bucket_tail(leaf))) << "one thread wrote a tail";
        tails += two.store->exists(stitch::files::bucket_tail(leaf)) ? 1 : 0;
        const std::vector<std::string> expected = records(one, leaf);
        EXPECT_TRUE(records(two, leaf) == expected) << "leaf " << leaf << ": the records differ";
        entries += expected.size();
    }
    EXPECT_GT(tails, 0u) << "the passes did not run in two parts";
    EXPECT_GT(entries, input.size()) << "features in several buckets (halos)";
    // Stopped from this thread's progress: the second part ends too, and the error comes out.
    const auto stopping = [](std::uint64_t done, std::uint64_t) {
        if (done > 0) {
            throw std::runtime_error("interrupted");
        }
    };
    EXPECT_THROW(made(tiling::make_memory_store(), 2, stopping), std::runtime_error);
}

// A store whose appends to files whose names end with `suffix` fail as a full disk does.
class FullFor : public tiling::WorkStore {
public:
    FullFor(tiling::WorkStore& inner, std::string suffix) : m_inner(inner), m_suffix(std::move(suffix)) {}
    std::unique_ptr<tiling::OutFile> create(const std::string& name) override { return m_inner.create(name); }
    std::unique_ptr<tiling::InFile> open(const std::string& name) const override { return m_inner.open(name); }
    bool exists(const std::string& name) const override { return m_inner.exists(name); }
    void remove(const std::string& name) override { m_inner.remove(name); }
    void remove_all(const std::string& prefix) override { m_inner.remove_all(prefix); }
    void append(const std::string& name, std::string_view bytes) override
    {
        if (name.size() >= m_suffix.size() && name.compare(name.size() - m_suffix.size(), m_suffix.size(), m_suffix) == 0) {
            throw tiling::disk_full_error(name + ": cannot write: No space left on device", "full");
        }
        m_inner.append(name, bytes);
    }
    std::uint64_t size(const std::string& name) const override { return m_inner.size(name); }
    std::uint64_t total_bytes() const override { return m_inner.total_bytes(); }
    std::uint64_t free_space() const override { return m_inner.free_space(); }
    bool on_disk() const override { return m_inner.on_disk(); }
    std::string where() const override { return m_inner.where(); }

private:
    tiling::WorkStore& m_inner;
    std::string m_suffix;
};

// A write that fails in either half of the spool's passes comes out of make_buckets() as that
// error, on the caller's thread, whichever half met it (the other half stops; no hang, no
// terminate), and the buckets of a run that succeeds after it on the same store are whole.
TEST_P(StoreTest, AFailedWriteInEitherHalfOfTheSpoolComesOutOnce)
{
    const double t = 0.01;
    const std::vector<Feature> input = perturbed_grid_coverage(80, 80, 1.0, 0.2, 9, 8, 0.004);
    auto store = make();
    stitch::SpoolMeta meta = spool_features(*store, input, t);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 20000;
    stitch::BucketOptions bo;
    bo.halo = 4 * t;
    bo.seam_band = 2 * t + 4e-9;
    bo.threads = 2;
    bo.least_part_bytes = std::uint64_t{1} << 20;
    bo.buffer_bytes = 1 << 16; // appends all along each half, not only at its end
    const tiling::PlanInput sample = meta.sample.take_vertices();
    for (const std::string suffix : {".tail", "-0", "-1", "-2", "-3"}) { // the second half's files; the first's
        SCOPED_TRACE(suffix);
        FullFor full(*store, suffix);
        try {
            stitch::make_buckets(full, meta, sample, tiling, bo);
            ADD_FAILURE() << "no error";
        } catch (const tiling::disk_full_error& e) {
            EXPECT_NE(std::string(e.what()).find(suffix), std::string::npos) << e.what();
        }
    }
    const stitch::TileLayout layout = stitch::make_buckets(*store, meta, sample, tiling, bo);
    std::uint64_t entries = 0;
    for (std::size_t leaf = 0; leaf < layout.plan.size(); ++leaf) {
        const std::size_t n = stitch::read_bucket(*store, layout, meta, leaf).size();
        EXPECT_EQ(n, layout.bucket_features[leaf]) << "leaf " << leaf;
        entries += n;
    }
    EXPECT_GT(entries, input.size());
}

// A spool cut to outlines reads back exactly the outlines it held, and nothing whole any more.
TEST_P(StoreTest, ASpoolCutToOutlinesKeepsItsOutlinesAndNothingElse)
{
    auto store = make();
    spool_features(*store, coverage_line_and_rejected(6, 5), 0.01);
    // The outlines as records: equal records are equal outlines, bit for bit.
    auto outlines = [&] {
        std::vector<std::string> out;
        stitch::SpooledFeatures in(*store, true);
        detail::CleanFeature cf;
        bool has_z = false;
        while (in.next(cf, has_z)) {
            tiling::ByteWriter w(out.emplace_back());
            tiling::put_clean_feature(w, cf, has_z);
        }
        return out;
    };
    const std::vector<std::string> before = outlines();
    ASSERT_EQ(before.size(), 6u * 6u + 2u);
    const std::uint64_t bytes = store->total_bytes();
    EXPECT_FALSE(stitch::spool_cut_to_outlines(*store));
    stitch::cut_spool_to_outlines(*store);
    EXPECT_TRUE(stitch::spool_cut_to_outlines(*store));
    EXPECT_FALSE(store->exists(stitch::files::features));
    EXPECT_FALSE(store->exists(stitch::files::offsets));
    EXPECT_LT(store->total_bytes(), bytes) << "the cut spool holds as much as before";
    stitch::cut_spool_to_outlines(*store); // again: nothing to do
    EXPECT_EQ(outlines(), before);
    EXPECT_THROW(stitch::SpooledFeatures(*store, false), tiling::work_error) << "whole features read from outlines";
    EXPECT_THROW(stitch::FeatureLookup{*store}, tiling::work_error);
}

INSTANTIATE_TEST_SUITE_P(Stores, StoreTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? std::string("Directory") : std::string("Memory"); });

// A full disk, made with /dev/full (every write fails with ENOSPC) under the names the store
// writes through: a committed file's temporary name, and an appended file's own name.
TEST(DirectoryStore, FullDiskIsADiskFullErrorNamingTheDirectory)
{
    if (!fs::exists("/dev/full")) {
        GTEST_SKIP() << "no /dev/full";
    }
    const fs::path dir = fs::temp_directory_path() / ("trisnap-full-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    auto store = tiling::make_directory_store(dir.string());
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    fs::create_symlink("/dev/full", dir / ("features.bin.tmp-" + std::string(host) + "-" + std::to_string(::getpid())));
    fs::create_symlink("/dev/full", dir / "bucket-0");
    auto expect_full = [&](const std::function<void()>& write) {
        try {
            write();
            ADD_FAILURE() << "no error";
        } catch (const tiling::disk_full_error& e) {
            EXPECT_EQ(e.directory(), dir.string());
            EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
        }
    };
    expect_full([&] {
        auto f = store->create("features.bin");
        f->write(std::string(3 << 20, 'x')); // more than the buffer: written at once
        f->commit();
    });
    expect_full([&] { store->append("bucket-0", "bytes"); });
    // Another failure stays a plain work_error.
    try {
        store->open("missing");
        ADD_FAILURE() << "no error";
    } catch (const tiling::disk_full_error&) {
        ADD_FAILURE() << "a missing file is not a full disk";
    } catch (const tiling::work_error&) {
    }
    fs::remove_all(dir);
}

/// Every ring point of the features, in order (closing points included).
std::vector<Coord> ring_points(const std::vector<Feature>& features)
{
    std::vector<Coord> pts;
    for (const Feature& f : features) {
        for (const Polygon& p : f.geometry.polygons) {
            for (const Path& r : p.rings) {
                pts.insert(pts.end(), r.begin(), r.end());
            }
        }
    }
    return pts;
}

TEST(VertexSample, DoesNotDependOnInputOrderAndKeepsEverythingUnderItsCap)
{
    const std::vector<Coord> pts = ring_points(perturbed_grid_coverage(40, 40, 1.0, 0.2, 5, 2));
    auto sample_of = [&](std::size_t cap, unsigned seed) {
        std::vector<Coord> order = pts;
        std::mt19937 rng(seed);
        std::shuffle(order.begin(), order.end(), rng);
        tiling::VertexSample s(cap);
        for (const Coord& c : order) {
            s.add(c.x, c.y);
        }
        tiling::PlanInput in = s.take();
        // Its memory too: 16 bytes a vertex up to the cap and the one over it that raises the
        // level, not a doubling's twice that (the vectors come out of take() as they were held).
        EXPECT_LE(in.xs.capacity(), std::max<std::size_t>(cap, 16) + 1);
        EXPECT_LE(in.ys.capacity(), std::max<std::size_t>(cap, 16) + 1);
        std::vector<std::pair<double, double>> xy;
        for (std::size_t i = 0; i < in.xs.size(); ++i) {
            xy.emplace_back(in.xs[i], in.ys[i]);
        }
        std::sort(xy.begin(), xy.end());
        return std::make_pair(in.level, xy);
    };
    const auto full = sample_of(pts.size(), 1);
    EXPECT_EQ(full.first, 0);
    EXPECT_EQ(full.second.size(), pts.size());
    const auto a = sample_of(pts.size() / 10, 1);
    const auto b = sample_of(pts.size() / 10, 2);
    EXPECT_GE(a.first, 4);
    EXPECT_LE(a.second.size(), pts.size() / 10);
    EXPECT_GT(a.second.size(), pts.size() / 40);
    EXPECT_EQ(a, b);
}

// The read phase's second reader (app/read_phase.cpp) samples its part of the layer apart:
// appended, the sample must be the one the whole sequence gives, in the same order, wherever the
// layer is cut and whatever levels each part reached on its own.
TEST(VertexSample, AppendedPartsGiveTheSequentialSample)
{
    std::vector<Coord> pts = ring_points(perturbed_grid_coverage(30, 30, 1.0, 0.2, 7, 2));
    pts.push_back({std::nan(""), 1.0}); // not counted by either
    std::size_t levels_apart = 0; // cuts where the two parts reached different levels alone
    for (const std::size_t cap : {pts.size(), pts.size() / 5, pts.size() / 40, std::size_t{16}}) {
        tiling::VertexSample whole(cap);
        for (const Coord& c : pts) {
            whole.add(c.x, c.y);
        }
        const tiling::PlanInput expected = whole.take();
        for (const std::size_t cut : {std::size_t{0}, std::size_t{1}, pts.size() / 7, pts.size() / 2, pts.size() - 3, pts.size()}) {
            tiling::VertexSample first(cap);
            tiling::VertexSample second(cap);
            for (std::size_t i = 0; i < pts.size(); ++i) {
                (i < cut ? first : second).add(pts[i].x, pts[i].y);
            }
            levels_apart += tiling::VertexSample(first).take().level != tiling::VertexSample(second).take().level;
            first.append(std::move(second));
            const tiling::PlanInput got = first.take();
            SCOPED_TRACE("cap " + std::to_string(cap) + ", cut at " + std::to_string(cut));
            EXPECT_LE(got.xs.capacity(), cap + 1) << "the appended sample held more than its cap";
            EXPECT_LE(got.ys.capacity(), cap + 1);
            EXPECT_EQ(got.level, expected.level);
            EXPECT_EQ(got.vertices, expected.vertices);
            EXPECT_EQ(got.xs, expected.xs);
            EXPECT_EQ(got.ys, expected.ys);
            EXPECT_EQ(got.extent.xmin, expected.extent.xmin);
            EXPECT_EQ(got.extent.ymin, expected.extent.ymin);
            EXPECT_EQ(got.extent.xmax, expected.extent.xmax);
            EXPECT_EQ(got.extent.ymax, expected.extent.ymax);
        }
        if (cap == pts.size() / 40) {
            EXPECT_GE(expected.level, 4);
        }
    }
    EXPECT_GT(levels_apart, 0u) << "no cut had its parts at different levels: append()'s re-filtering went untested";
}

TEST(TilePlan, SurvivesSaveLoadAndSplits)
{
    const auto features = perturbed_grid_coverage(20, 20, 10.0, 0.2, 6);
    tiling::PlanOptions o;
    o.vertex_budget = 500;
    tiling::TilePlan plan = tiling::make_plan(features, o);
    const std::size_t leaves = plan.size();
    const Region before = plan.core(3);
    const double mid = std::isfinite(before.xmin) && std::isfinite(before.xmax) ? 0.5 * (before.xmin + before.xmax) : 100.0;
    const std::size_t upper = plan.split_leaf(3, 0, mid);
    EXPECT_EQ(upper, leaves);
    EXPECT_EQ(plan.core(3).xmax, mid);
    EXPECT_EQ(plan.core(upper).xmin, mid);
    std::string bytes;
    tiling::ByteWriter w(bytes);
    plan.save(w);
    tiling::ByteReader r(bytes, "plan");
    const tiling::TilePlan back = tiling::TilePlan::load(r);
    ASSERT_EQ(back.size(), plan.size());
    std::mt19937_64 rng(1);
    for (int i = 0; i < 2000; ++i) {
        const double x = uniform(rng, -20, 220);
        const double y = uniform(rng, -20, 220);
        const std::size_t leaf = back.leaf_of(x, y);
        EXPECT_EQ(leaf, plan.leaf_of(x, y));
        EXPECT_TRUE(back.core(leaf).contains(x, y));
    }
}

// A directory store, a memory pool small enough that the balanced plan's tiles must be split,
// and a run stopped after a few tiles then continued: the untiled output, bit for bit.
TEST(TiledRun, SmallPoolSplitsTilesAndAResumedRunEqualsUntiled)
{
    const double t = 0.01;
    const auto input = perturbed_grid_coverage(40, 40, 1.0, 0.2, 7, 1, 0.004);
    const SnapOptions options = options_at(t);
    const SnapResult untiled = snap(input, options);
    const fs::path dir = fs::temp_directory_path() / ("trisnap-run-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 100000; // one leaf, unless the pool forces more
    tiling.threads = 2;
    stitch::ScheduleOptions schedule;
    schedule.threads = 2;
    schedule.memory_pool = schedule.model.tile_bytes(3000);
    std::size_t runs_first = 0;
    {
        auto store = tiling::make_directory_store(dir.string());
        stitch::SpoolMeta meta = spool_features(*store, input, t, 1000, 64); // a sampled plan, FIDs checked in runs
        EXPECT_TRUE(meta.fids_unique);
        EXPECT_GT(meta.sample.level, 0);
        stitch::TiledRun run(*store, options, tiling, schedule);
        run.plan(meta);
        EXPECT_GT(run.layout().plan.size(), 4u) << "the pool must have split the tiles";
        for (std::uint64_t v : run.layout().bucket_vertices) {
            EXPECT_LE(v, schedule.model.vertices_within(schedule.memory_pool));
        }
        int started = 0;
        stitch::ScheduleOptions stopping = schedule;
        stopping.check_cancel = [&] {
            if (++started > 3) {
                throw std::runtime_error("stop");
            }
        };
        stitch::TiledRun interrupted(*store, options, tiling, stopping);
        interrupted.plan(meta);
        EXPECT_THROW(interrupted.snap(), std::runtime_error);
        runs_first = interrupted.stats().tile_runs;
        EXPECT_GT(interrupted.missing().size(), 0u);
    }
    auto store = tiling::make_directory_store(dir.string());
    const std::string meta_bytes = store->get(stitch::files::spool_meta);
    tiling::ByteReader r(meta_bytes, "meta");
    stitch::SpoolMeta meta = stitch::SpoolMeta::load(r);
    stitch::TiledRun run(*store, options, tiling, schedule);
    run.plan(meta);
    const std::size_t live = run.groups().live(run.layout()).size();
    const std::size_t missing = run.missing().size();
    EXPECT_LT(missing, live) << "the first run finished no tile";
    EXPECT_GE(live - missing, runs_first);
    run.snap();
    EXPECT_EQ(run.stats().tile_runs, missing) << "finished tiles ran again";
    EXPECT_TRUE(run.missing().empty());
    run.stitch();
    expect_untiled_output(run, untiled, input.size());
    fs::remove_all(dir);
}

// A plan of one leaf in memory (--no-tiles) cuts its spool to outlines once its tile has its
// features, and the output is still the untiled one; where a later step may read the features
// whole (a directory store: --resume; --on-error skip: the retries; a halo that may grow) the
// spool stays whole.
TEST(TiledRun, APlanOfOneLeafInMemoryKeepsOnlyOutlinesOfItsSpool)
{
    const double t = 0.01;
    const std::vector<Feature> input = coverage_line_and_rejected(12, 9);
    const SnapOptions options = options_at(t);
    const SnapResult untiled = snap(input, options);
    const fs::path dir = fs::temp_directory_path() / ("trisnap-outline-" + std::to_string(::getpid()));
    struct Case {
        const char* what;
        bool on_disk;
        stitch::OnError on_error;
        int max_growth;
        bool cut;
    };
    for (const Case& c : {Case{"memory", false, stitch::OnError::stop, 0, true},
                          Case{"directory", true, stitch::OnError::stop, 0, false},
                          Case{"--on-error skip", false, stitch::OnError::skip, 0, false},
                          Case{"--halo-max-growth 2", false, stitch::OnError::stop, 2, false}}) {
        SCOPED_TRACE(c.what);
        fs::remove_all(dir);
        auto store = c.on_disk ? tiling::make_directory_store(dir.string()) : tiling::make_memory_store();
        stitch::SpoolMeta meta = spool_features(*store, input, t);
        stitch::TilingOptions tiling;
        tiling.plan.single = true;
        tiling.on_error = c.on_error;
        tiling.max_growth = c.max_growth;
        stitch::TiledRun run(*store, options, tiling, stitch::ScheduleOptions{});
        run.plan(meta);
        ASSERT_EQ(run.layout().plan.size(), 1u);
        run.snap();
        EXPECT_EQ(stitch::spool_cut_to_outlines(*store), c.cut);
        EXPECT_EQ(store->exists(stitch::files::features), !c.cut);
        run.stitch();
        expect_untiled_output(run, untiled, input.size());
    }
    fs::remove_all(dir);
}

// The stitch phase counts tiles: it starts at 0 of the live tiles, never goes back, and ends with
// every tile checked (done == total, the total the phase started with when no seam disagreed).
TEST(TiledRun, StitchReportsTilesCheckedOfARealTotal)
{
    const double t = 0.01;
    const auto input = perturbed_grid_coverage(16, 16, 1.0, 0.2, 9, 1, 0.004);
    auto store = tiling::make_memory_store();
    stitch::SpoolMeta meta = spool_features(*store, input, t, 100000, 1 << 10);
    stitch::TilingOptions tiling;
    tiling.plan.tile_size = 4.0;
    tiling.threads = 2;
    stitch::ScheduleOptions schedule;
    schedule.threads = 2;
    stitch::TiledRun run(*store, options_at(t), tiling, schedule);
    run.plan(meta);
    run.snap();
    const std::uint64_t live = run.groups().live(run.layout()).size();
    ASSERT_GT(live, 4u);
    std::vector<std::pair<std::uint64_t, std::uint64_t>> calls;
    run.stitch([&](std::uint64_t done, std::uint64_t total) { calls.emplace_back(done, total); });
    ASSERT_EQ(run.stats().seam_merges, 0u) << "the layer was meant to stitch in one round";
    ASSERT_GE(calls.size(), live) << "fewer reports than tiles";
    EXPECT_EQ(calls.front(), std::make_pair(std::uint64_t{0}, live));
    for (std::size_t i = 1; i < calls.size(); ++i) {
        EXPECT_GE(calls[i].first, calls[i - 1].first) << "call " << i << " went back";
        EXPECT_LE(calls[i].first, calls[i].second) << "call " << i;
        EXPECT_EQ(calls[i].second, live) << "call " << i;
    }
    EXPECT_EQ(calls.back(), std::make_pair(live, live));
}

// One tile (as with --no-tiles): the bar moves while the engine works, and Ctrl-C stops it inside
// the tile instead of after it. Nothing of the stopped tile is committed.
TEST(TiledRun, OneBigTileReportsProgressInsideAndStopsInside)
{
    const double t = 0.01;
    const auto input = perturbed_grid_coverage(60, 60, 1.0, 0.02, 7, 3, 0.004);
    const SnapOptions options = options_at(t);
    stitch::TilingOptions tiling;
    tiling.plan.vertex_budget = 10000000;
    tiling.threads = 1;
    stitch::ScheduleOptions schedule;
    schedule.threads = 1;
    {
        auto store = tiling::make_memory_store();
        stitch::SpoolMeta meta = spool_features(*store, input, t);
        stitch::TiledRun run(*store, options, tiling, schedule);
        run.plan(meta);
        ASSERT_EQ(run.layout().plan.size(), 1u);
        std::vector<std::pair<std::uint64_t, std::uint64_t>> calls;
        run.snap([&](std::uint64_t done, std::uint64_t total) { calls.emplace_back(done, total); });
        ASSERT_GE(calls.size(), 5u) << "one tile gave one jump of the bar";
        for (std::size_t i = 1; i < calls.size(); ++i) {
            EXPECT_GE(calls[i].first, calls[i - 1].first) << "call " << i << " went back";
            EXPECT_EQ(calls[i].second, calls[0].second);
        }
        EXPECT_LT(calls.front().first, calls.front().second);
        EXPECT_EQ(calls.back().first, calls.back().second);
        EXPECT_TRUE(run.missing().empty());
    }
    auto store = tiling::make_memory_store();
    stitch::SpoolMeta meta = spool_features(*store, input, t);
    int checks = 0;
    stitch::ScheduleOptions stopping = schedule;
    stopping.check_cancel = [&] {
        if (++checks == 3) { // the first check is the scheduler's, before the tile starts
            throw std::runtime_error("stop");
        }
    };
    stitch::TiledRun run(*store, options, tiling, stopping);
    run.plan(meta);
    EXPECT_THROW(run.snap(), std::runtime_error);
    EXPECT_EQ(checks, 3) << "the engine went on after the cancel";
    EXPECT_EQ(run.stats().tile_runs, 0u);
    EXPECT_EQ(run.missing().size(), 1u) << "a stopped tile left a result";
}

} // namespace
} // namespace trisnap
