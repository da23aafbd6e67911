// Tiled snapping (issue 5) on the largest layers of ../shared/data, in process on pre-loaded
// features (reading and writing are bench_pipeline's business):
//   Tiling/<layer>/untiled     one triangulation (snap(), as --no-tiles)
//   Tiling/<layer>/tiles:1     default balanced tiles, 1 thread   -> overhead = this / untiled - 1
//   Tiling/<layer>/tiles:2     the same on 2 threads              -> speed-up = tiles:1 / tiles:2
//   Spool/<layer>              the spool phase alone: the plan, then the reach and bucket passes
//                              over the spooled layer (make_buckets()), one thread
//   Stitch/<layer>             the stitched output alone (OutputMerger over tiles snapped once),
//                              one thread
// Counters: tiles, seam merges, halo growths, and `identical` = share of features equal to the
// untiled output (tile invariance), measured once per layer outside the timing.
// bench/tiling runs this with repetitions and writes bench/results/tiling.json (medians).
#include "app/allocator.hpp"
#include "core/snap.hpp"
#include "core/wkt.hpp"
#include "ogr_layer_reader.hpp"
#include "stitch/spool.hpp"
#include "stitch/output.hpp"
#include "stitch/tiled_snap.hpp"
#include "tiling/tile_input.hpp"
#include "tiling/work_store.hpp"
#include "test_data.hpp"

#include <benchmark/benchmark.h>

#include <limits>
#include <map>
#include <memory>
#include <string>

namespace trisnap {
namespace {

struct Layer {
    const char* name;
    const char* file;
    const char* layer;
    double tolerance;
};

constexpr Layer layers[] = {
    {"ne_10m_land", "natural_earth/natural_earth.gpkg", "ne_10m_land", 1e-5},
    {"jakarta_buildings", "osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg", "building", 1e-6},
    {"monaco_multipolygons", "osm_monaco_osrm_2020/monaco_osrm_2020.gpkg", "multipolygons", 1e-6},
    {"andorra", "snapoly_andorra/andorra.gpkg", "andorra", 1e-6},
};

struct Loaded {
    std::vector<Feature> features;
    double identical = -1; ///< share of features equal to the untiled output (once)
};

Loaded* load(const Layer& l)
{
    static std::map<std::string, std::unique_ptr<Loaded>> cache;
    auto& slot = cache[l.name];
    if (!slot) {
        slot = std::make_unique<Loaded>();
        if (auto path = shared_data(l.file)) slot->features = read_ogr_layer(*path, l.layer).features;
    }
    return slot.get();
}

/// The layer, or nullptr when its data set is absent (the benchmark then skips with a message).
Loaded* load_or_skip(benchmark::State& state, const Layer& l)
{
    Loaded* d = load(l);
    if (d->features.empty()) {
        state.SkipWithError((std::string("data set absent: ") + l.file).c_str());
        return nullptr;
    }
    return d;
}

/// The layer spooled into `store` as the read phase spools it.
stitch::SpoolMeta spool_layer(tiling::WorkStore& store, const std::vector<Feature>& features, double tolerance,
                              std::size_t sample_cap, std::size_t fid_buffer)
{
    stitch::FeatureSpool spool(store, tolerance, sample_cap, fid_buffer);
    std::vector<Problem> problems;
    for (std::size_t i = 0; i < features.size(); ++i) {
        spool.add(i, features[i].id, features[i].geometry, problems);
    }
    return spool.finish();
}

double identical_share(Loaded& d, const SnapOptions& o)
{
    if (d.identical >= 0) return d.identical;
    const SnapResult a = snap(d.features, o);
    const stitch::TiledResult b = stitch::snap_tiled(d.features, o, stitch::TilingOptions{});
    std::size_t same = 0;
    for (std::size_t i = 0; i < a.features.size(); ++i)
        same += to_wkt(a.features[i].geometry) == to_wkt(b.result.features[i].geometry);
    d.identical = static_cast<double>(same) / static_cast<double>(a.features.size());
    return d.identical;
}

void BM_Tiling(benchmark::State& state, Layer l, int threads)
{
    Loaded* d = load_or_skip(state, l);
    if (d == nullptr) {
        return;
    }
    SnapOptions o;
    o.tolerance = l.tolerance;
    stitch::TilingOptions tiling;
    tiling.threads = threads;
    stitch::StitchStats last;
    for (auto _ : state) {
        if (threads == 0) {
            SnapResult r = snap(d->features, o);
            benchmark::DoNotOptimize(r.features.data());
        } else {
            stitch::TiledResult r = stitch::snap_tiled(d->features, o, tiling);
            last = r.stitch;
            benchmark::DoNotOptimize(r.result.features.data());
        }
    }
    state.counters["features"] = static_cast<double>(d->features.size());
    if (threads > 0) {
        state.counters["tiles"] = static_cast<double>(last.tiles);
        state.counters["seam_merges"] = static_cast<double>(last.seam_merges);
        state.counters["halo_growths"] = static_cast<double>(last.halo_growths);
        state.counters["identical"] = identical_share(*d, o);
    }
}

// The layer spooled once into a store in memory (as the read phase does); each iteration plans
// it and fills the buckets again, as the spool phase does (make_buckets() clears them first).
void BM_Spool(benchmark::State& state, Layer l)
{
    Loaded* d = load_or_skip(state, l);
    if (d == nullptr) {
        return;
    }
    const std::unique_ptr<tiling::WorkStore> store = tiling::make_memory_store();
    const stitch::SpoolMeta meta = spool_layer(*store, d->features, l.tolerance, std::size_t{16} << 20, std::size_t{1} << 30);
    std::uint64_t to_snap = 0; // spooled and not rejected by the cleaning: each in a bucket at least
    {
        stitch::SpooledFeatures in(*store);
        detail::CleanFeature cf;
        bool has_z = false;
        while (in.next(cf, has_z)) {
            to_snap += !cf.rejected;
        }
    }
    const stitch::TilingOptions tiling;
    stitch::BucketOptions options;
    options.halo = tiling.halo_factor * l.tolerance;
    options.seam_band = 2 * l.tolerance;
    std::size_t leaves = 0;
    std::uint64_t entries = 0;
    for (auto _ : state) {
        tiling::PlanInput sample = meta.sample;
        const stitch::TileLayout layout = stitch::make_buckets(*store, meta, std::move(sample), tiling, options);
        leaves = layout.plan.size();
        entries = 0;
        for (const std::uint64_t n : layout.bucket_features) {
            entries += n;
        }
    }
    if (entries < to_snap) {
        state.SkipWithError("the buckets hold fewer features than the spool gave to snap");
        return;
    }
    state.counters["features"] = static_cast<double>(d->features.size());
    state.counters["tiles"] = static_cast<double>(leaves);
    state.counters["bucket_entries"] = static_cast<double>(entries);
}

// The stitch alone: the layer spooled, planned and its tiles snapped once, into a store in
// memory; each iteration drains a new OutputMerger over the tiles' results (what the write
// phase's stitched side does: the pieces read back, a feature across tiles traced again). On
// Natural Earth's land most of it is one feature across all 16 tiles (REPORT.md, "The stitch's
// memory"). Counters: assembled (features traced again), copied (taken whole from one tile).
void BM_Stitch(benchmark::State& state, Layer l)
{
    Loaded* d = load_or_skip(state, l);
    if (d == nullptr) {
        return;
    }
    SnapOptions o;
    o.tolerance = l.tolerance;
    const stitch::TilingOptions tiling;
    const std::unique_ptr<tiling::WorkStore> store = tiling::make_memory_store();
    // Caps as snap_tiled's: the whole sample and every FID in memory.
    stitch::SpoolMeta meta = spool_layer(*store, d->features, o.tolerance, std::numeric_limits<std::size_t>::max(),
                                         std::numeric_limits<std::size_t>::max());
    stitch::ScheduleOptions schedule;
    schedule.threads = 1;
    stitch::TiledRun run(*store, o, tiling, schedule);
    run.plan(meta);
    run.snap();
    run.stitch();
    std::size_t features = 0;
    std::uint64_t vertices = 0;
    stitch::OutputCounts counts;
    for (auto _ : state) {
        const std::unique_ptr<stitch::OutputMerger> merger = run.output();
        stitch::OutputItem item;
        features = 0;
        vertices = 0;
        while (merger->next(item)) {
            ++features;
            vertices += tiling::engine_vertices(item.output.geometry);
        }
        counts = merger->counts();
    }
    if (features != d->features.size()) {
        state.SkipWithError("the stitch gave a different number of features than the layer has");
        return;
    }
    state.counters["features"] = static_cast<double>(features);
    state.counters["output_vertices"] = static_cast<double>(vertices);
    state.counters["assembled"] = static_cast<double>(counts.assembled);
    state.counters["copied"] = static_cast<double>(counts.copied);
}

int register_all()
{
    for (const Layer& l : layers) {
        const std::string base = std::string("Tiling/") + l.name;
        benchmark::RegisterBenchmark((base + "/untiled").c_str(), BM_Tiling, l, 0)->Unit(benchmark::kMillisecond)->UseRealTime();
        benchmark::RegisterBenchmark((base + "/tiles:1").c_str(), BM_Tiling, l, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
        benchmark::RegisterBenchmark((base + "/tiles:2").c_str(), BM_Tiling, l, 2)->Unit(benchmark::kMillisecond)->UseRealTime();
        benchmark::RegisterBenchmark((std::string("Spool/") + l.name).c_str(), BM_Spool, l)->Unit(benchmark::kMillisecond)->UseRealTime();
        benchmark::RegisterBenchmark((std::string("Stitch/") + l.name).c_str(), BM_Stitch, l)->Unit(benchmark::kMillisecond)->UseRealTime();
    }
    return 0;
}

const int registered = register_all();

} // namespace
} // namespace trisnap

int main(int argc, char** argv)
{
    trisnap::keep_freed_memory(); // as the trisnap binary
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
        return 2;
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
