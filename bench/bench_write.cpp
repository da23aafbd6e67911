// OUT's writer alone (io/writer.hpp), on one thread: a real layer's features, converted to the
// engine's geometries once before timing, written to a new GeoPackage as the write phase writes
// snapped features: `Write/rows/<layer>` as GeoPackage rows (io/gpkg_rows.hpp: the values taken,
// the blob encoded, the row inserted), `Write/gdal/<layer>` through GDAL (to_ogr, an OGRFeature,
// CreateFeature). Both include the commit (the spatial index, the close). Fails when a feature
// is refused or the file's count differs; skips with "data set absent" without ../shared/data.
// `Write/rows-index-on-disk/<layer>`: the rows path with the index's box budget an eighth of the
// layer's features, so its boxes are sorted in runs on disk and the tree packed from their merge
// (the bytes are the in-memory packing's; tests/unit/io). `PackRtree/<n>`: the spatial index's
// packing alone, on generated boxes.
// bench/README.md, "The writer".
#include "io/gpkg_rows.hpp"
#include "io/gpkg_rtree.hpp"
#include "io/ogr_geometry.hpp"
#include "io/writer.hpp"
#include "test_data.hpp"

#include <benchmark/benchmark.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

namespace trisnap {
namespace {

namespace fs = std::filesystem;

struct Layer {
    const char* name;
    const char* relative;
    const char* layer;
};

constexpr Layer layers[] = {
    {"andorra", "snapoly_andorra/andorra.gpkg", "andorra"},
    {"jakarta", "osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg", "building"},
};

/// The layer read once: its features (attributes) and their engine geometries.
struct Input {
    GDALDatasetUniquePtr dataset;
    OGRLayer* layer = nullptr;
    std::vector<OGRFeatureUniquePtr> features;
    std::vector<Geometry> geometries;
    std::vector<OGRwkbGeometryType> types;
    std::size_t vertices = 0;
};

std::unique_ptr<Input> read_input(const std::string& path, const char* name)
{
    auto in = std::make_unique<Input>();
    in->dataset.reset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    in->layer = in->dataset ? in->dataset->GetLayerByName(name) : nullptr;
    if (in->layer == nullptr) {
        return nullptr;
    }
    for (auto& f : *in->layer) {
        Geometry g;
        if (from_ogr(f->GetGeometryRef(), g) != GeometryVerdict::snap) {
            continue;
        }
        in->vertices += static_cast<std::size_t>(count_vertices(f->GetGeometryRef()));
        in->types.push_back(wkbFlatten(f->GetGeometryRef()->getGeometryType()));
        f->SetGeometryDirectly(nullptr);
        in->geometries.push_back(std::move(g));
        in->features.emplace_back(f.release());
    }
    return in;
}

void BM_Write(benchmark::State& state, const Layer& layer, bool rows, bool index_on_disk = false)
{
    GDALAllRegister();
    const auto path = shared_data(layer.relative);
    if (!path) {
        state.SkipWithError(("data set absent: " + std::string(layer.relative)).c_str());
        return;
    }
    const std::unique_ptr<Input> in = read_input(*path, layer.layer);
    if (!in) {
        state.SkipWithError("cannot read the layer");
        return;
    }
    const fs::path dir = fs::temp_directory_path() / ("trisnap-bench-write-" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string out = (dir / "out.gpkg").string();
    bool took_rows = false;
    for (auto _ : state) {
        fs::remove(out);
        WriteOptions options;
        options.path = out;
        options.rows = rows;
        if (index_on_disk) {
            options.index_boxes = std::max<std::size_t>(in->features.size() / 8, 1);
        }
        LayerWriter writer(options, *in->layer);
        writer.expect(0, in->features.size());
        const GpkgRows* r = writer.rows(0);
        took_rows = r != nullptr;
        GpkgGeometry blob;
        GpkgValues values;
        for (std::size_t i = 0; i < in->features.size(); ++i) {
            const OGRFeature& f = *in->features[i];
            std::string error;
            if (r != nullptr) {
                r->take(f, f.GetFID(), values);
                encode_gpkg(in->geometries[i], in->types[i], r->srs_id(), blob);
                writer.write_row(0, values, blob);
            } else {
                error = writer.write(0, f, f.GetFID(), to_ogr(in->geometries[i], in->types[i]));
            }
            if (!error.empty()) {
                state.SkipWithError(("feature refused: " + error).c_str());
                fs::remove_all(dir);
                return;
            }
        }
        writer.commit();
        if (const auto refused = writer.take_refusals(); !refused.empty()) {
            state.SkipWithError(("feature refused: " + refused.front().message).c_str());
            fs::remove_all(dir);
            return;
        }
    }
    GDALDatasetUniquePtr check(GDALDataset::Open(out.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr));
    const GIntBig written = check ? check->GetLayer(0)->GetFeatureCount() : -1;
    check.reset();
    fs::remove_all(dir);
    if (written != static_cast<GIntBig>(in->features.size()) || took_rows != rows) {
        state.SkipWithError(("wrote " + std::to_string(written) + " of " + std::to_string(in->features.size()) +
                             (took_rows != rows ? "; the rows path was not the one asked for" : ""))
                                .c_str());
        return;
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * in->features.size()));
    state.counters["features"] = static_cast<double>(in->features.size());
    state.counters["vertices"] = static_cast<double>(in->vertices);
}

/// The spatial index's packing alone (io/gpkg_rtree.hpp, `pack_rtree`): `n` small boxes spread
/// at random, cut into nodes of SQLite's 51 cells. The write phase packs once per layer, after
/// its last feature: serial time at every thread count.
void BM_PackRtree(benchmark::State& state)
{
    const auto n = static_cast<std::size_t>(state.range(0));
    std::vector<RtreeEntry> boxes;
    std::uint64_t seed = 12345;
    const auto next = [&seed] {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(seed >> 11) / 9007199254740992.0;
    };
    for (std::size_t i = 0; i < n; ++i) {
        OGREnvelope box;
        box.MinX = next() * 10000;
        box.MinY = next() * 10000;
        box.MaxX = box.MinX + 5;
        box.MaxY = box.MinY + 5;
        boxes.push_back(rtree_entry(static_cast<std::int64_t>(i + 1), box));
    }
    std::size_t leaves = 0;
    for (auto _ : state) {
        const PackedRtree tree = pack_rtree(boxes, 51);
        leaves = tree.nodes.size() - tree.first_leaf;
        benchmark::DoNotOptimize(tree.nodes.data());
    }
    if (leaves != (n + 50) / 51) {
        state.SkipWithError(("packed into " + std::to_string(leaves) + " leaves, not " + std::to_string((n + 50) / 51)).c_str());
        return;
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}

[[maybe_unused]] const bool registered = [] {
    benchmark::RegisterBenchmark("PackRtree", BM_PackRtree)->Arg(20000)->Arg(250000)->Unit(benchmark::kMillisecond);
    for (const Layer& layer : layers) {
        for (const bool rows : {true, false}) {
            benchmark::RegisterBenchmark((std::string("Write/") + (rows ? "rows/" : "gdal/") + layer.name).c_str(),
                                         [&layer, rows](benchmark::State& s) { BM_Write(s, layer, rows); })
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
        }
        benchmark::RegisterBenchmark((std::string("Write/rows-index-on-disk/") + layer.name).c_str(),
                                     [&layer](benchmark::State& s) { BM_Write(s, layer, true, true); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    return true;
}();

} // namespace
} // namespace trisnap

BENCHMARK_MAIN();
