// End-to-end benchmarks of `trisnap snap` (issue 3); bench/README.md says what each one measures.
// Each iteration does what SnapCommand::run() does, in process, through the app library:
// make_plan() (open the input, choose the layer, count, resolve the tolerance), then
// run_pipeline() (read, one engine call, write-then-rename). Only the report JSON and the summary
// are left out. In process rather than by spawning the binary, so that the per-phase seconds come
// straight from RunResult and process start-up is not timed; peak memory is measured per
// iteration by resetting the kernel's high-water mark (see PeakMemory).
#include "app/allocator.hpp"
#include "app/command.hpp"
#include "app/options.hpp"
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "app/progress.hpp"
#include "app/report.hpp"
#include "io/writer.hpp"
#include "test_data.hpp"

#include <benchmark/benchmark.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace trisnap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// One real layer and the options a user would give for it.
struct DataSet {
    const char* name;
    const char* relative;  ///< under the data folder
    const char* layer;
    double tolerance;
    bool metres;           ///< --tolerance-m (else --tolerance, layer units)
};

// Andorra: EPSG:4326, 1e-6 degrees is about 10 cm. BGT Delft: RD New metres, 1 cm.
// OSM: the driver's multipolygons layer, 5 cm converted to degrees at the mean latitude.
constexpr DataSet data_sets[] = {
    {"andorra", "snapoly_andorra/andorra.gpkg", "andorra", 1e-6, false},
    {"bgt_delft", "bgt_delft_3dfier/bgt_delft.gpkg", "bgt_maaiveld_partition", 0.01, false},
    {"osm_andorra", "osm_small_extracts/andorra_graphhopper_2013.osm.pbf", "multipolygons", 0.05, true},
};

struct OutputFormat {
    const char* name;
    const char* extension; ///< the writer picks the driver from it, as the CLI does
};

constexpr OutputFormat formats[] = {{"gpkg", ".gpkg"}, {"fgb", ".fgb"}};

/// $TRISNAP_DATA when set, else the shared data folder configured at build time.
fs::path data_root() {
    const char* env = std::getenv("TRISNAP_DATA");
    return env != nullptr && *env != '\0' ? fs::path(env) : fs::path(TRISNAP_SHARED_DATA);
}

/// Where the outputs go: one folder per process, removed by main().
const fs::path& output_dir() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("trisnap_bench_pipeline_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

/// Peak resident memory of one iteration. Linux keeps one high-water mark per process; writing
/// 5 to /proc/self/clear_refs resets it to the current RSS (Linux >= 4.0), so each iteration
/// starts from what the process already holds (libraries, GDAL's drivers: like a fresh CLI run,
/// give or take the benchmark library). Freed heap is returned first (malloc_trim) so an earlier,
/// bigger run does not set the floor. Where the reset is refused, the figure is the process-wide
/// peak so far and the row is labelled so.
class PeakMemory {
public:
    /// Call outside the timed region.
    void reset() {
#if defined(__GLIBC__)
        ::malloc_trim(0);
#endif
        std::ofstream clear("/proc/self/clear_refs");
        clear << "5" << std::flush;
        m_reset_ok = m_reset_ok && static_cast<bool>(clear);
    }
    /// The high-water mark since the last reset, in MB.
    double read_mb() const {
        std::ifstream status("/proc/self/status");
        for (std::string line; std::getline(status, line);)
            if (line.rfind("VmHWM:", 0) == 0) {
                std::istringstream fields(line.substr(6));
                double kib = 0;
                fields >> kib;
                return kib / 1024.0;
            }
        return peak_memory_mb(); // no /proc: getrusage, process-wide
    }
    bool reset_ok() const { return m_reset_ok; }

private:
    bool m_reset_ok = true;
};

/// The arguments the CLI would parse from
/// `trisnap snap IN OUT --layer L --tolerance[-m] T --overwrite --progress never`.
SnapArgs snap_args(const DataSet& data, const fs::path& input, const OutputFormat& format) {
    SnapArgs args;
    args.input = input.string();
    args.output = (output_dir() / (std::string(data.name) + format.extension)).string();
    args.layers = {data.layer};
    if (data.metres)
        args.tolerance_m = data.tolerance;
    else
        args.tolerance = data.tolerance;
    args.overwrite = true; // every iteration replaces the previous output, as a rerun would
    args.progress = "never";
    return args;
}

/// Sums over the iterations of one benchmark.
struct Totals {
    double open_s = 0, read_s = 0, snap_s = 0, write_s = 0, peak_mb = 0;
    std::size_t features = 0, vertices = 0, written = 0, problems = 0;

    void add(const RunResult& r, double open_seconds) {
        open_s += open_seconds;
        read_s += r.seconds_read;
        snap_s += r.seconds_snap;
        write_s += r.seconds_write;
        features = r.input;
        vertices = r.input_vertices;
        written = r.written;
        problems = r.problems.size();
    }
};

/// Counters per call: the phases are the pipeline's own stopwatch (open_s is make_plan(), timed
/// here); peak_mb is the largest of the iterations.
void report(benchmark::State& state, const Totals& t) {
    using benchmark::Counter;
    state.counters["features"] = Counter(static_cast<double>(t.features));
    state.counters["vertices"] = Counter(static_cast<double>(t.vertices));
    state.counters["written"] = Counter(static_cast<double>(t.written));
    state.counters["problems"] = Counter(static_cast<double>(t.problems));
    state.counters["open_s"] = Counter(t.open_s, Counter::kAvgIterations);
    state.counters["read_s"] = Counter(t.read_s, Counter::kAvgIterations);
    state.counters["snap_s"] = Counter(t.snap_s, Counter::kAvgIterations);
    state.counters["write_s"] = Counter(t.write_s, Counter::kAvgIterations);
    state.counters["peak_mb"] = Counter(t.peak_mb);
    state.SetItemsProcessed(static_cast<std::int64_t>(t.vertices) * state.iterations());
}

void bm_pipeline(benchmark::State& state, const DataSet& data, const OutputFormat& format) {
    const fs::path input = data_root() / data.relative;
    std::error_code ec;
    if (!fs::exists(input, ec)) {
        const std::string message = "data set absent: " + input.string() + " (set TRISNAP_DATA to the data folder)";
        state.SkipWithError(message.c_str());
        return;
    }
    SnapArgs args = snap_args(data, input, format);
    args.threads = static_cast<int>(state.range(0)); // as --threads N (write_s: the writer thread)
    const Config config = resolve_config(args);
    const ThreadLimit limit(config.run.threads);
    Totals totals;
    PeakMemory memory;
    for (auto _ : state) {
        state.PauseTiming();
        memory.reset();
        state.ResumeTiming();
        try {
            Plan plan;
            Progress progress(args.progress, false);
            InterruptGuard interrupt;
            const RunResult r = snap_run(args, config, progress, plan, interrupt);
            totals.add(r, r.seconds_open);
        } catch (const std::exception& e) {
            state.SkipWithError((std::string("pipeline failed: ") + e.what()).c_str());
            break;
        }
        totals.peak_mb = std::max(totals.peak_mb, memory.read_mb());
    }
    if (!memory.reset_ok()) state.SetLabel("peak_mb process-wide (cannot reset VmHWM)");
    report(state, totals);
}

// The GeoPackage writer's spatial index (io/gpkg_rtree.hpp) against GDAL's own build of it, the
// anchor measured in the same run: `n` small squares spread at random written through
// LayerWriter and committed. "bulk": the writer's packed index; "gdal": GDAL's CreateSpatialIndex()
// (the writer's fallback, GDAL 3.6's build for a new layer: one SQLite insertion per feature);
// "none": SPATIAL_INDEX=NO, the write without any index.
enum class IndexBuild { bulk, gdal, none };

void bm_gpkg_index(benchmark::State& state, IndexBuild build) {
    const int n = static_cast<int>(state.range(0));
    GDALDatasetUniquePtr memory(GetGDALDriverManager()->GetDriverByName("Memory")->Create("", 0, 0, 0, GDT_Unknown, nullptr));
    OGRLayer* source = memory->CreateLayer("squares", nullptr, wkbPolygon, nullptr);
    std::vector<std::unique_ptr<OGRGeometry>> squares;
    std::uint64_t seed = 12345;
    const auto next = [&seed] {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(seed >> 11) / 9007199254740992.0;
    };
    for (int i = 0; i < n; ++i) {
        const double x = next() * 10000;
        const double y = next() * 10000;
        auto ring = std::make_unique<OGRLinearRing>();
        ring->addPoint(x, y);
        ring->addPoint(x + 5, y);
        ring->addPoint(x + 5, y + 5);
        ring->addPoint(x, y);
        auto polygon = std::make_unique<OGRPolygon>();
        polygon->addRingDirectly(ring.release());
        squares.push_back(std::move(polygon));
    }
    const std::string path = (output_dir() / "index.gpkg").string();
    OGRFeature feature(source->GetLayerDefn());
    for (auto _ : state) {
        std::error_code ec;
        fs::remove(path, ec);
        WriteOptions options;
        options.path = path;
        if (build == IndexBuild::none) options.layer_options = {"SPATIAL_INDEX=NO"};
        if (build == IndexBuild::gdal) options.index_boxes = 0;
        try {
            LayerWriter writer(options, *source);
            for (int i = 0; i < n; ++i) writer.write(feature, i + 1, squares[static_cast<std::size_t>(i)]->clone());
            writer.commit();
        } catch (const std::exception& e) {
            state.SkipWithError((std::string("write failed: ") + e.what()).c_str());
            break;
        }
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(n) * state.iterations());
}

void register_benchmarks() {
    for (const auto& [name, build] : {std::pair{"BM_GpkgIndex/bulk", IndexBuild::bulk},
                                       std::pair{"BM_GpkgIndex/gdal", IndexBuild::gdal},
                                       std::pair{"BM_GpkgIndex/none", IndexBuild::none}}) {
        benchmark::RegisterBenchmark(name, [build = build](benchmark::State& state) { bm_gpkg_index(state, build); })
            ->Arg(20000)->Arg(200000)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
    }
    for (const DataSet& data : data_sets)
        for (const OutputFormat& format : formats) {
            const std::string name = std::string("BM_Pipeline/") + data.name + "/" + format.name;
            benchmark::RegisterBenchmark(name.c_str(), [&data, &format](benchmark::State& state) {
                bm_pipeline(state, data, format);
            })->ArgName("threads")->Arg(1)->Arg(2)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
        }
}

} // namespace
} // namespace trisnap

int main(int argc, char** argv) {
    trisnap::keep_freed_memory(); // as the trisnap binary
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv))
        return 2;
    GDALAllRegister();
    trisnap::setup_logging(0, 0); // as the CLI without -v/-q: warnings on stderr, GDAL's chatter hidden
    trisnap::register_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::error_code ec;
    std::filesystem::remove_all(trisnap::output_dir(), ec);
    return 0;
}
