// Engine benchmarks (issue 2, "Benchmark"); bench/README.md says what each one measures.
// Inputs come from the tests' generators (tests/support) and from ../shared/data; they are built
// or loaded once, outside the timed loops, and shared by every benchmark that uses them.
// Every benchmark times whole trisnap::snap() calls except the two phase benchmarks, which feed
// the engine's own per-phase stopwatch to Google Benchmark as manual time.
#include "core/snap.hpp"
#include "generators.hpp"
#include "ogr_layer_reader.hpp"
#include "test_data.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace trisnap {
namespace {

// Coverage: unit cells, corners jittered by up to 0.2 cell, two extra points per edge wiggled
// sideways by up to 0.002 cell (the generator's default): 13 vertices per cell ring, closing
// point included.
constexpr double coverage_cell = 1.0;
constexpr double coverage_jitter = 0.2;
constexpr int coverage_points_per_edge = 2;
constexpr std::uint64_t coverage_seed = 2;
// t relative to the cell: at 0.05 cell about 5% of the triangulation's vertices are merged away
// or split into an edge (counter snapped_share; calibrated here, see README.md), so the
// fix-point has real work; nearly all of it is merges of edge points closer than t.
constexpr double coverage_t = 0.05 * coverage_cell;

constexpr double degenerate_t = 1.0;
constexpr std::uint64_t degenerate_seed = 5;

constexpr double andorra_t = 1e-6; // degrees, about 10 cm at 42.5 N

enum class Timed { whole_run, triangulate_phase, snap_phase, label_phase, extract_phase };

bool env_is_set(const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr && std::string(value) == "1";
}

/// A coverage with about `vertices` vertices (closing points included), built once per size.
const std::vector<Feature>& coverage(std::int64_t vertices) {
    static std::map<std::int64_t, std::vector<Feature>> cache;
    auto [it, fresh] = cache.try_emplace(vertices);
    if (fresh) {
        const double cells = static_cast<double>(vertices) / (5 + 4 * coverage_points_per_edge);
        const int side = std::max(1, static_cast<int>(std::lround(std::sqrt(cells))));
        it->second = perturbed_grid_coverage(side, side, coverage_cell, coverage_jitter,
                                              coverage_seed, coverage_points_per_edge);
    }
    return it->second;
}

/// n near-degenerate polygons at t = 1, spread so that density stays the same at every n
/// (about a quarter of the area covered, neighbours often within t).
const std::vector<Feature>& near_degenerate(std::int64_t n) {
    static std::map<std::int64_t, std::vector<Feature>> cache;
    auto [it, fresh] = cache.try_emplace(n);
    if (fresh) {
        const double scale = 40.0 * degenerate_t * std::sqrt(static_cast<double>(n));
        it->second = near_degenerate_polygons(static_cast<int>(n), scale, degenerate_t,
                                              degenerate_seed);
    }
    return it->second;
}

/// $TRISNAP_DATA when set, else the shared data folder configured at build time.
std::filesystem::path data_root() {
    const char* env = std::getenv("TRISNAP_DATA");
    return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                          : std::filesystem::path(TRISNAP_SHARED_DATA);
}

/// A real layer, loaded on first use; `error` is set instead when it is absent or unreadable.
struct RealLayer {
    std::vector<Feature> features;
    std::string error;
};

const RealLayer& andorra() {
    static const RealLayer layer = [] {
        RealLayer out;
        const std::filesystem::path path = data_root() / "snapoly_andorra" / "andorra.gpkg";
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            out.error = "data set absent: " + path.string() + " (set TRISNAP_DATA to the data folder)";
            return out;
        }
        try {
            out.features = read_ogr_layer(path.string(), "andorra").features;
        } catch (const std::exception& e) {
            out.error = std::string("cannot load Andorra: ") + e.what();
        }
        return out;
    }();
    return layer;
}

SnapOptions options_at(double t) {
    SnapOptions options;
    options.tolerance = t;
    return options;
}

/// Engine counters, per call: what the fix-point did and where the time went. `vertices` is the
/// engine's input count (closing points excluded, a shared boundary counted on both sides);
/// `mesh_vertices` counts each location once.
void report(benchmark::State& state, const SnapStats& sum, std::size_t problems) {
    using benchmark::Counter;
    const auto calls = static_cast<double>(state.iterations());
    const double vertices = calls > 0 ? static_cast<double>(sum.input_vertices) / calls : 0.0;
    state.counters["vertices"] = Counter(vertices);
    state.counters["mesh_vertices"] =
        Counter(static_cast<double>(sum.triangulation_vertices), Counter::kAvgIterations);
    state.counters["merges"] = Counter(static_cast<double>(sum.merges), Counter::kAvgIterations);
    state.counters["splits"] = Counter(static_cast<double>(sum.splits), Counter::kAvgIterations);
    state.counters["snapped_share"] = Counter(sum.triangulation_vertices > 0
        ? static_cast<double>(sum.merges + sum.splits) / static_cast<double>(sum.triangulation_vertices)
        : 0.0);
    state.counters["problems"] = Counter(static_cast<double>(problems), Counter::kAvgIterations);
    state.counters["triangulate_s"] = Counter(sum.seconds_triangulate, Counter::kAvgIterations);
    state.counters["snap_s"] = Counter(sum.seconds_snap, Counter::kAvgIterations);
    state.counters["label_s"] = Counter(sum.seconds_label, Counter::kAvgIterations);
    state.counters["extract_s"] = Counter(sum.seconds_extract, Counter::kAvgIterations);
    state.counters["snap_over_triangulate"] =
        Counter(sum.seconds_triangulate > 0 ? sum.seconds_snap / sum.seconds_triangulate : 0.0);
    state.SetItemsProcessed(static_cast<std::int64_t>(sum.input_vertices));
    state.SetComplexityN(static_cast<std::int64_t>(vertices));
}

/// The engine's own stopwatch for one phase of a call.
double phase_seconds(const SnapStats& stats, Timed timed) {
    switch (timed) {
    case Timed::triangulate_phase:
        return stats.seconds_triangulate;
    case Timed::snap_phase:
        return stats.seconds_snap;
    case Timed::label_phase:
        return stats.seconds_label;
    case Timed::extract_phase:
        return stats.seconds_extract;
    default:
        return 0.0;
    }
}

/// Runs snap() on `features` at `t` for every iteration; `timed` picks what the reported time is.
void run_snap(benchmark::State& state, const std::vector<Feature>& features, double t, Timed timed,
              const SnapProgress& progress = {}) {
    SnapOptions options = options_at(t);
    options.progress = progress;
    SnapStats sum;
    std::size_t problems = 0;
    for (auto _ : state) {
        SnapResult result = snap(features, options);
        benchmark::DoNotOptimize(result.features.data());
        if (timed != Timed::whole_run)
            state.SetIterationTime(phase_seconds(result.stats, timed));
        sum += result.stats;
        problems += result.problems.size();
    }
    report(state, sum, problems);
}

void bm_snap_coverage(benchmark::State& state) {
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::whole_run);
}

/// The same with a progress callback that does what the CLI's does per call (an atomic flag for
/// Ctrl-C, a count for the bar): its cost is the difference to BM_Snap_Coverage (target: < 1 %).
void bm_snap_coverage_progress(benchmark::State& state) {
    static std::atomic<int> signal{0};
    std::size_t calls = 0;
    std::size_t last = 0;
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::whole_run, [&](std::size_t done, std::size_t) {
        if (signal.load() != 0) {
            throw std::runtime_error("interrupted");
        }
        last = done;
        ++calls;
    });
    benchmark::DoNotOptimize(last);
    state.counters["progress_calls_per_run"] = benchmark::Counter(static_cast<double>(calls) / static_cast<double>(state.iterations()));
}

void bm_triangulate_only(benchmark::State& state) {
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::triangulate_phase);
}

void bm_snap_only(benchmark::State& state) {
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::snap_phase);
}

void bm_label_only(benchmark::State& state) {
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::label_phase);
}

void bm_extract_only(benchmark::State& state) {
    run_snap(state, coverage(state.range(0)), coverage_t, Timed::extract_phase);
}

/// Andorra, timed as `timed` says; skipped when the data set is absent.
void run_andorra(benchmark::State& state, Timed timed) {
    const RealLayer& layer = andorra();
    if (!layer.error.empty()) {
        state.SkipWithError(layer.error.c_str());
        return;
    }
    run_snap(state, layer.features, andorra_t, timed);
}

/// Andorra, one phase of whole calls (state.range(0) is a Timed value).
void bm_andorra_phase(benchmark::State& state) {
    run_andorra(state, static_cast<Timed>(state.range(0)));
}

void bm_snap_near_degenerate(benchmark::State& state) {
    run_snap(state, near_degenerate(state.range(0)), degenerate_t, Timed::whole_run);
}

void bm_snap_andorra(benchmark::State& state) {
    run_andorra(state, Timed::whole_run);
}

/// Coverage sizes: 10^3..10^5 vertices, and 10^6 with TRISNAP_BENCH_LARGE=1.
std::vector<std::int64_t> coverage_sizes() {
    std::vector<std::int64_t> sizes{1'000, 10'000, 100'000};
    if (env_is_set("TRISNAP_BENCH_LARGE"))
        sizes.push_back(1'000'000);
    return sizes;
}

void with_sizes(benchmark::internal::Benchmark* b, const std::vector<std::int64_t>& sizes) {
    for (std::int64_t n : sizes)
        b->Arg(n);
    b->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);
}

void register_benchmarks() {
    using benchmark::RegisterBenchmark;
    const std::vector<std::int64_t> sizes = coverage_sizes();
    with_sizes(RegisterBenchmark("BM_Snap_Coverage", bm_snap_coverage)
                   ->MeasureProcessCPUTime()->UseRealTime(), sizes);
    with_sizes(RegisterBenchmark("BM_Snap_Coverage_Progress", bm_snap_coverage_progress)
                   ->MeasureProcessCPUTime()->UseRealTime(), sizes);
    // The two phases of whole calls on the same inputs, timed by the engine's own stopwatch
    // (snap.hpp has no triangulate-only entry point, and a private one would measure something
    // else): snapping should cost no more than building the triangulation. Compare the rows, or
    // the snap_over_triangulate counter, which pairs the phases of the same calls.
    with_sizes(RegisterBenchmark("BM_Triangulate_Only", bm_triangulate_only)->UseManualTime(),
               sizes);
    with_sizes(RegisterBenchmark("BM_Snap_Only", bm_snap_only)->UseManualTime(), sizes);
    with_sizes(RegisterBenchmark("BM_Label_Only", bm_label_only)->UseManualTime(), sizes);
    with_sizes(RegisterBenchmark("BM_Extract_Only", bm_extract_only)->UseManualTime(), sizes);
    // Andorra per phase: Arg 1 triangulate, 2 snap, 3 label, 4 extract (the Timed values).
    RegisterBenchmark("BM_Andorra_Phase", bm_andorra_phase)
        ->DenseRange(static_cast<int>(Timed::triangulate_phase), static_cast<int>(Timed::extract_phase))
        ->UseManualTime()->Unit(benchmark::kMillisecond);
    with_sizes(RegisterBenchmark("BM_Snap_NearDegenerate", bm_snap_near_degenerate)
                   ->MeasureProcessCPUTime()->UseRealTime(), {100, 1'000, 10'000});
    RegisterBenchmark("BM_Snap_Andorra", bm_snap_andorra)
        ->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
}

} // namespace
} // namespace trisnap

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv))
        return 2;
    trisnap::register_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
