// Does handing features from one thread to another pay on this machine? GDAL alone, no trisnap
// code: the numbers behind bench/results/REPORT.md, "Handing features between threads: freeing
// them on the wrong thread is what loses", and the reason trisnap's writer thread (app/handoff.hpp) frees each
// batch on the thread that made it.
//   read                 the layer read (geometry envelope per feature), one thread;
//   write                features read earlier cloned and written to a new GeoPackage (no
//                        spatial index, one transaction), one thread;
//   read_beside_write    both at once on two threads, each on its own features: the writer's
//                        loop and the reader, each timed on its thread (the wall column also
//                        holds creating, committing and freeing);
//   write_made_elsewhere the write of features another thread cloned earlier (not concurrently):
//                        the writer's CPU seconds, against `write`'s;
//   serial               read + clone + write on one thread;
//   pipeline             one thread reads and clones, another writes; batches of 256 through a
//                        queue of 4 batches; the writer frees the features;
//   pipeline_back        the same, each batch handed back and freed by the thread that made it.
// And, before and after the passes, what every handoff pays underneath: the round trip of one
// cache line between two threads (spinning on an atomic, 200,000 trips or one second), in ns. On the
// team's VM it is either ~120-200 ns or ~450-600 ns, and the writer thread's gain follows it
// (bench/results/REPORT.md, "The cores' distance").
// Medians of --runs passes each (wall seconds, and the writer's CPU seconds where it is a thread
// of its own). Warm page cache: one read before the passes. `--round-trip` prints the round trip
// alone (ns, "nan" with one CPU) and exits: bench/threads records it beside its runs.
//   bench_handoff IN [--layer NAME] [--runs N] [--work DIR] [--json FILE]
//   bench_handoff --round-trip
#include <CLI/CLI.hpp>
#include <gdal_priv.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <ctime>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <sched.h>
#include <unistd.h>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using Batch = std::vector<OGRFeature*>;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double thread_cpu()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

nlohmann::json number_or_null(double v)
{
    return std::isnan(v) ? nlohmann::json() : nlohmann::json(v);
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Nanoseconds for one cache line to go to another thread and back: each side spins until the
/// line holds its value, then writes the other's; 200,000 trips or as many as one second allows
/// (a busy machine, where the two take turns by time slices). NaN with one CPU to run on.
double cross_core_round_trip_ns()
{
    cpu_set_t cpus;
    if (sched_getaffinity(0, sizeof cpus, &cpus) != 0 || CPU_COUNT(&cpus) < 2) {
        return std::nan("");
    }
    constexpr int k_trips = 200000;
    alignas(64) std::atomic<int> line{0};
    std::atomic<bool> stop{false};
    std::thread other([&] {
        for (;;) {
            int seen = 0;
            while ((seen = line.load(std::memory_order_acquire)) == 0) {
                if (stop.load(std::memory_order_relaxed)) {
                    return;
                }
            }
            if (seen == 2) {
                return;
            }
            line.store(0, std::memory_order_release);
        }
    });
    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::seconds(1);
    int trips = 0;
    for (bool late = false; trips < k_trips && !late; ++trips) {
        if (trips % 8 == 7 && Clock::now() > deadline) {
            break;
        }
        line.store(1, std::memory_order_release);
        for (unsigned spin = 1; line.load(std::memory_order_acquire) != 0; ++spin) {
            if (spin % 4096 == 0 && Clock::now() > deadline) {
                late = true;
                break;
            }
        }
    }
    const double seconds = since(t0);
    line.store(2, std::memory_order_release); // the other side ends, whether it is waiting or not
    stop.store(true, std::memory_order_relaxed);
    other.join();
    return seconds * 1e9 / trips;
}

/// A bounded queue of batches; `close()` ends it.
class Queue {
public:
    explicit Queue(std::size_t capacity) : m_capacity(capacity) {}
    void push(Batch b)
    {
        std::unique_lock lock(m_mutex);
        m_changed.wait(lock, [&] { return m_batches.size() < m_capacity; });
        m_batches.push_back(std::move(b));
        m_changed.notify_all();
    }
    bool pop(Batch& b, bool wait = true)
    {
        std::unique_lock lock(m_mutex);
        if (wait) {
            m_changed.wait(lock, [&] { return !m_batches.empty() || m_closed; });
        }
        if (m_batches.empty()) {
            return false;
        }
        b = std::move(m_batches.front());
        m_batches.pop_front();
        m_changed.notify_all();
        return true;
    }
    void close()
    {
        std::unique_lock lock(m_mutex);
        m_closed = true;
        m_changed.notify_all();
    }

private:
    std::size_t m_capacity;
    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::deque<Batch> m_batches;
    bool m_closed = false;
};

struct Input {
    std::string path, layer;
};

OGRLayer* open_layer(const Input& in, GDALDatasetUniquePtr& ds)
{
    ds.reset(GDALDataset::Open(in.path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds) {
        throw std::runtime_error("cannot open " + in.path);
    }
    OGRLayer* l = in.layer.empty() ? ds->GetLayer(0) : ds->GetLayerByName(in.layer.c_str());
    if (!l) {
        throw std::runtime_error("no layer '" + in.layer + "' in " + in.path);
    }
    return l;
}

/// A new GeoPackage layer like `defn`, inside a transaction; commit() closes it. Every write is
/// checked: a failure stops the benchmark.
class Output {
public:
    /// The features are the input layer's own (their definition is `defn`): the output's geometry
    /// column takes the input's name, so that GeoPackage's insert names the right column.
    Output(const std::string& path, OGRFeatureDefn* defn)
    {
        std::filesystem::remove(path);
        GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
        m_ds.reset(gpkg->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
        if (!m_ds) {
            throw std::runtime_error("cannot create " + path);
        }
        CPLStringList options;
        options.SetNameValue("SPATIAL_INDEX", "NO");
        if (defn->GetGeomFieldCount() > 0 && defn->GetGeomFieldDefn(0)->GetNameRef()[0] != '\0') {
            options.SetNameValue("GEOMETRY_NAME", defn->GetGeomFieldDefn(0)->GetNameRef());
        }
        m_layer = m_ds->CreateLayer("features", nullptr, defn->GetGeomType(), options.List());
        for (int i = 0; m_layer && i < defn->GetFieldCount(); ++i) {
            if (m_layer->CreateField(defn->GetFieldDefn(i)) != OGRERR_NONE) {
                throw std::runtime_error("cannot create field " + std::to_string(i) + " in " + path);
            }
        }
        if (!m_layer || m_layer->StartTransaction() != OGRERR_NONE) {
            throw std::runtime_error("cannot start writing " + path);
        }
    }
    void write(OGRFeature* f)
    {
        f->SetFID(OGRNullFID);
        if (m_layer->CreateFeature(f) != OGRERR_NONE) {
            throw std::runtime_error("CreateFeature failed");
        }
    }
    void commit()
    {
        if (m_layer->CommitTransaction() != OGRERR_NONE) {
            throw std::runtime_error("cannot commit the output");
        }
        CPLErrorReset();
        m_ds.reset(); // closes the file: GDAL 3.6 reports a failed close only as an error
        if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal) {
            throw std::runtime_error(std::string("cannot close the output: ") + CPLGetLastErrorMsg());
        }
    }

private:
    GDALDatasetUniquePtr m_ds;
    OGRLayer* m_layer = nullptr;
};

/// Reads every feature; `f` sees each (it may take it over by releasing the pointer).
double read_all(const Input& in, const std::function<void(OGRFeatureUniquePtr&)>& f)
{
    GDALDatasetUniquePtr ds;
    OGRLayer* l = open_layer(in, ds);
    const auto t0 = Clock::now();
    l->ResetReading();
    for (OGRFeatureUniquePtr feature(l->GetNextFeature()); feature; feature.reset(l->GetNextFeature())) {
        f(feature);
    }
    return since(t0);
}

void touch(OGRFeatureUniquePtr& f)
{
    if (const OGRGeometry* g = f->GetGeometryRef()) {
        OGREnvelope e;
        g->getEnvelope(&e);
    }
}

struct Pass {
    explicit Pass(std::string n) : name(std::move(n)) {}
    std::string name;
    std::vector<double> wall, cpu, other; ///< `other`: the second thread's wall where there is one
};

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"handing features between threads: read, write, side by side, and as a pipeline"};
    Input in;
    int runs = 3;
    std::string work = std::filesystem::temp_directory_path().string(), json;
    bool round_trip_only = false;
    app.add_option("IN", in.path);
    app.add_flag("--round-trip", round_trip_only, "print a cache line's round trip between two threads (ns) and exit");
    app.add_option("--layer", in.layer);
    app.add_option("--runs", runs, "passes per setup (medians)")->check(CLI::Range(1, 100));
    app.add_option("--work", work, "directory for the GeoPackages written");
    app.add_option("--json", json, "write the medians as JSON here");
    CLI11_PARSE(app, argc, argv);
    if (round_trip_only) {
        std::printf("%.0f\n", cross_core_round_trip_ns());
        return 0;
    }
    if (in.path.empty()) {
        std::fprintf(stderr, "bench_handoff: IN is required (or --round-trip)\n");
        return 2;
    }
    GDALAllRegister();
    const std::string out_a = (std::filesystem::path(work) / ("handoff-" + std::to_string(::getpid()) + "-a.gpkg")).string();
    const std::string out_b = (std::filesystem::path(work) / ("handoff-" + std::to_string(::getpid()) + "-b.gpkg")).string();
    std::vector<Pass> passes;
    std::vector<double> round_trips{cross_core_round_trip_ns()};
    try {
        GDALDatasetUniquePtr keep;
        OGRFeatureDefn* defn = open_layer(in, keep)->GetLayerDefn();
        Batch loaded;
        read_all(in, [&](OGRFeatureUniquePtr& f) { loaded.push_back(f.release()); }); // warms the cache too
        const auto clones = [&] {
            Batch b;
            for (OGRFeature* f : loaded) {
                b.push_back(f->Clone());
            }
            return b;
        };
        const auto write_batch = [&](Batch& b, const std::string& path) {
            Output out(path, defn);
            const double c0 = thread_cpu();
            const auto t0 = Clock::now();
            for (OGRFeature* f : b) {
                out.write(f);
            }
            const double wall = since(t0), cpu = thread_cpu() - c0;
            out.commit();
            for (OGRFeature* f : b) {
                OGRFeature::DestroyFeature(f);
            }
            return std::make_pair(wall, cpu);
        };
        Pass read("read"), write("write"), beside("read_beside_write"), elsewhere("write_made_elsewhere"),
            serial("serial"), pipeline("pipeline"), back("pipeline_back");
        for (int r = 0; r < runs; ++r) {
            read.wall.push_back(read_all(in, touch));
            {
                Batch b = clones();
                const auto [wall, cpu] = write_batch(b, out_a);
                write.wall.push_back(wall);
                write.cpu.push_back(cpu);
            }
            {
                Batch b = clones();
                double w_read = 0, w_write = 0, c_write = 0;
                const auto t0 = Clock::now();
                std::thread reader([&] { w_read = read_all(in, touch); });
                std::thread writer([&] { std::tie(w_write, c_write) = write_batch(b, out_a); });
                reader.join();
                writer.join();
                beside.wall.push_back(since(t0));
                beside.other.push_back(w_read);
                beside.cpu.push_back(c_write);
            }
            {
                Batch b;
                std::thread maker([&] { b = clones(); });
                maker.join();
                double wall = 0, cpu = 0;
                std::thread writer([&] { std::tie(wall, cpu) = write_batch(b, out_a); });
                writer.join();
                elsewhere.wall.push_back(wall);
                elsewhere.cpu.push_back(cpu);
            }
            {
                const auto t0 = Clock::now();
                Output out(out_a, defn);
                read_all(in, [&](OGRFeatureUniquePtr& f) {
                    OGRFeatureUniquePtr c(f->Clone());
                    out.write(c.get());
                });
                out.commit();
                serial.wall.push_back(since(t0));
            }
            for (const bool hand_back : {false, true}) {
                Queue queue(4), returned(1u << 30);
                Output out(out_b, defn);
                double cpu = 0;
                std::exception_ptr failed;
                const auto t0 = Clock::now();
                std::thread writer([&] {
                    const double c0 = thread_cpu();
                    try {
                        Batch b;
                        while (queue.pop(b)) {
                            for (OGRFeature* f : b) {
                                out.write(f);
                            }
                            if (hand_back) {
                                returned.push(std::move(b));
                            } else {
                                for (OGRFeature* f : b) {
                                    OGRFeature::DestroyFeature(f);
                                }
                            }
                        }
                    } catch (...) {
                        failed = std::current_exception();
                        Batch b;
                        while (queue.pop(b)) {
                            for (OGRFeature* f : b) {
                                OGRFeature::DestroyFeature(f);
                            }
                        }
                    }
                    cpu = thread_cpu() - c0;
                });
                const auto free_returned = [&](bool wait) {
                    Batch b;
                    while (returned.pop(b, wait)) {
                        for (OGRFeature* f : b) {
                            OGRFeature::DestroyFeature(f);
                        }
                    }
                };
                Batch batch;
                read_all(in, [&](OGRFeatureUniquePtr& f) {
                    batch.push_back(f->Clone());
                    if (batch.size() == 256) {
                        queue.push(std::move(batch));
                        batch.clear();
                        free_returned(false);
                    }
                });
                if (!batch.empty()) {
                    queue.push(std::move(batch));
                }
                queue.close();
                writer.join();
                returned.close();
                free_returned(true);
                if (failed) {
                    std::rethrow_exception(failed);
                }
                out.commit();
                Pass& p = hand_back ? back : pipeline;
                p.wall.push_back(since(t0));
                p.cpu.push_back(cpu);
            }
        }
        for (OGRFeature* f : loaded) {
            OGRFeature::DestroyFeature(f);
        }
        passes = {read, write, beside, elsewhere, serial, pipeline, back};
        round_trips.push_back(cross_core_round_trip_ns());
        std::printf("%zu features, medians of %d\n", loaded.size(), runs);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_handoff: %s\n", e.what());
        std::filesystem::remove(out_a);
        std::filesystem::remove(out_b);
        return 1;
    }
    std::filesystem::remove(out_a);
    std::filesystem::remove(out_b);
    std::printf("a cache line's round trip between two threads: %.0f ns before the passes, %.0f ns after\n", round_trips.front(),
                round_trips.back());
    std::printf("%-22s %10s %14s %16s\n", "setup", "wall s", "writer CPU s", "other thread s");
    for (const Pass& p : passes) {
        std::printf("%-22s %10.3f", p.name.c_str(), median(p.wall));
        if (p.cpu.empty()) {
            std::printf(" %14s", "-");
        } else {
            std::printf(" %14.3f", median(p.cpu));
        }
        if (p.other.empty()) {
            std::printf(" %16s\n", "-");
        } else {
            std::printf(" %16.3f\n", median(p.other));
        }
    }
    if (!json.empty()) {
        nlohmann::json doc = {{"input", in.path},
                              {"runs", runs},
                              {"round_trip_ns", {{"before", number_or_null(round_trips.front())}, {"after", number_or_null(round_trips.back())}}},
                              {"setups", nlohmann::json::array()}};
        for (const Pass& p : passes) {
            doc["setups"].push_back({{"name", p.name},
                                     {"wall_s", median(p.wall)},
                                     {"writer_cpu_s", p.cpu.empty() ? nlohmann::json() : nlohmann::json(median(p.cpu))},
                                     {"other_thread_s", p.other.empty() ? nlohmann::json() : nlohmann::json(median(p.other))}});
        }
        std::ofstream out(json);
        out << doc.dump(1) << "\n";
        out.close();
        if (!out) {
            std::fprintf(stderr, "bench_handoff: cannot write %s\n", json.c_str());
            return 1;
        }
    }
    return 0;
}
