// Adversarial inputs (issue 13): tolerances larger than the features and vertices closer than t
// along a straight line or an exact circle. Each input runs at its small and its large tolerance;
// the target is the large run within 10x of the small one (bench/README.md, "Adversarial").
// TRISNAP_BENCH_LARGE=1 runs the sizes the issue measured; the default is a tenth of them.
#include "core/snap.hpp"
#include "generators.hpp"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace trisnap {
namespace {

const std::vector<AdversarialCase>& cases() {
    static const std::vector<AdversarialCase> all = [] {
        const char* large = std::getenv("TRISNAP_BENCH_LARGE");
        const bool full = large != nullptr && std::string(large) == "1";
        return adversarial_cases(full ? 1.0 : 0.1);
    }();
    return all;
}

void run_case(benchmark::State& state, std::size_t index, bool large) {
    const AdversarialCase& c = cases()[index];
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
    for (std::size_t i = 0; i < cases().size(); ++i) {
        const AdversarialCase& c = cases()[i];
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
