// Adversarial inputs: tolerances larger than the features and vertices closer than t along a
// straight line or an exact circle (generated), Andorra at 0.001 degrees, CLC's one polygon at
// 0.5 degrees (near its own size) and JTS's ReducePrecisionFailure case 4 at its grid size 1223
// (real, skipped when ../shared/data is absent). Each input runs at its small and its large tolerance; the target is the large run
// within 10x of the small one, which bench/adversarial prints as ratios (bench/README.md,
// "Adversarial"). TRISNAP_BENCH_LARGE=1 runs the sizes the reliability review measured and a
// circle of 10^6 vertices; the default is a tenth of the generated sizes.
#include "core/snap.hpp"
#include "core/wkt.hpp"
#include "generators.hpp"
#include "ogr_layer_reader.hpp"
#include "peer_xml.hpp"
#include "test_data.hpp"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace trisnap {
namespace {

std::filesystem::path data_root() {
    const char* env = std::getenv("TRISNAP_DATA");
    return env != nullptr ? std::filesystem::path(env) : std::filesystem::path(TRISNAP_SHARED_DATA);
}

bool large_sizes() {
    const char* large = std::getenv("TRISNAP_BENCH_LARGE");
    return large != nullptr && std::string(large) == "1";
}

/// A layer of a GeoPackage under ../shared/data as one case at two tolerances (its path listed
/// as absent when the data set is not there).
void add_gpkg_layer(std::vector<AdversarialCase>& out, std::vector<std::string>& absent, const char* name,
                    const std::filesystem::path& relative, const char* layer, double small_t, double large_t) {
    const std::filesystem::path path = data_root() / relative;
    if (!std::filesystem::exists(path)) {
        absent.push_back(path.string());
        return;
    }
    out.push_back({name, read_ogr_layer(path.string(), layer).features, small_t, large_t});
}

/// The real layers: Andorra (5,757 buildings) at 1e-6 degrees (about 10 cm) and at 0.001 degrees
/// (about 90 m); CLC 2006's one polygon (43,925 vertices, 0.67 x 0.42 degrees) at 1e-5 and at 0.5
/// degrees, a tolerance near the layer's own size, where every vertex lies within t of most
/// others and constraints block many merges (300 s before the searches passed over parked
/// pairs); planetiler's NJ shore (one polygon of 254,531 vertices, 2.5 x 2.2 degrees, a few
/// straight edges along the sea) at 1e-5 and at 0.1 degrees: with one long edge anywhere every
/// vertex's walk covered its whole disk of the edge radius until the long edges got their grid
/// (core/long_edges.hpp): 443 s at 0.1 degrees, then 10 s.
void add_real_layers(std::vector<AdversarialCase>& out, std::vector<std::string>& absent) {
    add_gpkg_layer(out, absent, "andorra", "snapoly_andorra/andorra.gpkg", "andorra", 1e-6, 1e-3);
    add_gpkg_layer(out, absent, "clc_polygon", "clc2006_prepair/CLC2006_2018418.gpkg", "clc2006_2018418", 1e-5, 0.5);
    add_gpkg_layer(out, absent, "njshore", "osm_hard_polygons_planetiler/planetiler_hard_polygons.gpkg", "njshore",
                   1e-5, 0.1);
}

/// JTS's ReducePrecisionFailure case 4 (39,473 vertices) at t = 10 and at its grid size, 1223.
void add_jts(std::vector<AdversarialCase>& out, std::vector<std::string>& absent) {
    const std::filesystem::path path =
        data_root() / "peer_tests" / "jts_testxml" / "failure__TestReducePrecisionFailure.xml";
    std::ifstream file(path);
    if (!file) {
        absent.push_back(path.string());
        return;
    }
    std::stringstream text;
    text << file.rdbuf();
    const std::vector<XmlCase> xml = parse_xml_cases(text.str());
    if (xml.size() < 4 || !is_snappable_wkt(xml[3].a)) {
        absent.push_back(path.string() + " (no case 4)");
        return;
    }
    out.push_back({"jts_failure_case4", {Feature{1, read_wkt(xml[3].a)}}, 10.0, xml[3].grid_size});
}

struct Cases {
    std::vector<AdversarialCase> all;
    std::vector<std::string> absent; ///< real data sets not found
};

const Cases& cases() {
    static const Cases c = [] {
        Cases out;
        out.all = adversarial_cases(large_sizes() ? 1.0 : 0.1);
        if (large_sizes()) { // the review's 1 M circle (> 300 s before the one-candidate queue)
            out.all.push_back({"circle_1m", {circle(1, 1'000'000, 100.0, 0.0, 1)}, 1e-4, 0.01});
        }
        add_real_layers(out.all, out.absent);
        add_jts(out.all, out.absent);
        return out;
    }();
    return c;
}

void run_case(benchmark::State& state, std::size_t index, bool large) {
    const AdversarialCase& c = cases().all[index];
    SnapOptions options;
    options.tolerance = large ? c.large_t : c.small_t;
    SnapStats sum;
    for (auto _ : state) {
        SnapResult result = snap(c.features, options);
        benchmark::DoNotOptimize(result.features.data());
        sum += result.stats;
    }
    using benchmark::Counter;
    state.counters["vertices"] = Counter(static_cast<double>(sum.input_vertices), Counter::kAvgIterations);
    state.counters["merges"] = Counter(static_cast<double>(sum.merges), Counter::kAvgIterations);
    state.counters["splits"] = Counter(static_cast<double>(sum.splits), Counter::kAvgIterations);
    state.counters["faces_visited"] = Counter(static_cast<double>(sum.faces_visited), Counter::kAvgIterations);
    state.counters["snap_s"] = Counter(sum.seconds_snap, Counter::kAvgIterations);
    state.SetItemsProcessed(static_cast<std::int64_t>(sum.input_vertices));
}

void register_benchmarks() {
    for (std::size_t i = 0; i < cases().all.size(); ++i) {
        const AdversarialCase& c = cases().all[i];
        const std::string name = std::string("BM_Adversarial/") + c.name + "/" +
                                 std::to_string(vertex_count(c.features));
        for (const bool large : {false, true}) {
            benchmark::RegisterBenchmark((name + (large ? "/large_t" : "/small_t")).c_str(),
                                         [i, large](benchmark::State& s) { run_case(s, i, large); })
                ->MeasureProcessCPUTime()
                ->UseRealTime()
                ->Unit(benchmark::kMillisecond)
                ->Iterations(1);
        }
    }
    for (const std::string& path : cases().absent) {
        benchmark::RegisterBenchmark(("BM_Adversarial/absent/" + std::filesystem::path(path).stem().string()).c_str(),
                                     [path](benchmark::State& s) { s.SkipWithError(("data set absent: " + path).c_str()); });
    }
}

} // namespace
} // namespace trisnap

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
        return 2;
    }
    trisnap::register_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
