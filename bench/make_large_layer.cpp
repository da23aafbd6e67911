// Country-scale test layers from a real one: copies of a layer from ../shared/data laid over a
// grid of offsets (each copy shifted by the layer's extent plus a gap, so copies never touch),
// with every attribute and unique FIDs (copy x stride + FID), written as GeoPackage or
// FlatGeobuf in input order (FlatGeobuf without its spatial index, which would reorder it).
//   bench_make_large_layer IN OUT --polygons N [--layer NAME] [--format GPKG|FlatGeobuf]
// The source layer is read once into memory; copies stream to the output in transactions of
// 100,000 features. Output bytes depend only on the arguments.
#include <CLI/CLI.hpp>
#include <cpl_conv.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Source {
    std::vector<OGRFeatureUniquePtr> features;
    OGREnvelope extent;
    GIntBig max_fid = 0;
};

Source read_source(OGRLayer& layer)
{
    Source s;
    layer.ResetReading();
    while (OGRFeature* f = layer.GetNextFeature()) {
        s.max_fid = std::max<GIntBig>(s.max_fid, f->GetFID());
        if (const OGRGeometry* g = f->GetGeometryRef()) {
            OGREnvelope e;
            g->getEnvelope(&e);
            s.extent.Merge(e);
        }
        s.features.emplace_back(f);
    }
    return s;
}

void shift(OGRGeometry* g, double dx, double dy)
{
    if (auto* curve = dynamic_cast<OGRSimpleCurve*>(g)) {
        for (int i = 0; i < curve->getNumPoints(); ++i) {
            curve->setPoint(i, curve->getX(i) + dx, curve->getY(i) + dy, curve->getZ(i));
        }
        if (!g->Is3D()) {
            g->flattenTo2D();
        }
    } else if (auto* polygon = dynamic_cast<OGRCurvePolygon*>(g)) {
        for (int i = 0; i < polygon->getNumInteriorRings() + 1; ++i) {
            shift(i == 0 ? polygon->getExteriorRingCurve() : polygon->getInteriorRingCurve(i - 1), dx, dy);
        }
    } else if (auto* collection = dynamic_cast<OGRGeometryCollection*>(g)) {
        for (int i = 0; i < collection->getNumGeometries(); ++i) {
            shift(collection->getGeometryRef(i), dx, dy);
        }
    } else if (auto* point = dynamic_cast<OGRPoint*>(g)) {
        point->setX(point->getX() + dx);
        point->setY(point->getY() + dy);
    }
}

class Output {
public:
    Output(const std::string& path, const std::string& format, OGRLayer& source)
    {
        GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(format.c_str());
        if (!driver) {
            throw std::runtime_error("no GDAL driver " + format);
        }
        m_ds.reset(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
        if (!m_ds) {
            throw std::runtime_error("cannot create " + path + ": " + CPLGetLastErrorMsg());
        }
        char** options = nullptr;
        if (format == "FlatGeobuf") {
            options = CSLSetNameValue(options, "SPATIAL_INDEX", "NO");
        }
        m_layer = m_ds->CreateLayer(source.GetName(), source.GetSpatialRef(), source.GetGeomType(), options);
        CSLDestroy(options);
        if (!m_layer) {
            throw std::runtime_error("cannot create the layer in " + path + ": " + CPLGetLastErrorMsg());
        }
        const OGRFeatureDefn* defn = source.GetLayerDefn();
        for (int i = 0; i < defn->GetFieldCount(); ++i) {
            OGRFieldDefn field(defn->GetFieldDefn(i));
            if (m_layer->CreateField(&field) != OGRERR_NONE) {
                throw std::runtime_error(std::string("cannot create field ") + field.GetNameRef());
            }
        }
        m_transactions = m_ds->TestCapability(ODsCTransactions) != 0;
        begin();
    }
    void add(const OGRFeature& source, GIntBig fid, double dx, double dy)
    {
        OGRFeatureUniquePtr out(OGRFeature::CreateFeature(m_layer->GetLayerDefn()));
        out->SetFrom(&source, TRUE);
        out->SetFID(fid);
        if (OGRGeometry* g = out->GetGeometryRef()) {
            shift(g, dx, dy);
        }
        if (m_layer->CreateFeature(out.get()) != OGRERR_NONE) {
            throw std::runtime_error("cannot write feature " + std::to_string(fid) + ": " + CPLGetLastErrorMsg());
        }
        if (++m_pending == 100000) {
            commit();
            begin();
        }
    }
    void close()
    {
        commit();
        m_ds.reset();
    }

private:
    void begin()
    {
        if (m_transactions) {
            m_ds->StartTransaction();
        }
        m_pending = 0;
    }
    void commit()
    {
        if (m_transactions && m_ds->CommitTransaction() != OGRERR_NONE) {
            throw std::runtime_error(std::string("cannot commit: ") + CPLGetLastErrorMsg());
        }
    }

    GDALDatasetUniquePtr m_ds;
    OGRLayer* m_layer = nullptr;
    bool m_transactions = false;
    std::size_t m_pending = 0;
};

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"Lays copies of a real layer over a grid of offsets (benchmark data at country scale)"};
    std::string input;
    std::string output;
    std::string layer_name;
    std::string format = "GPKG";
    long long polygons = 0;
    app.add_option("IN", input, "source dataset")->required();
    app.add_option("OUT", output, "output dataset (must not exist)")->required();
    app.add_option("--polygons", polygons, "features in the output (the last copy is cut short)")->required();
    app.add_option("--layer", layer_name, "source layer (default: the first)");
    app.add_option("--format", format, "GPKG or FlatGeobuf")->check(CLI::IsMember({"GPKG", "FlatGeobuf"}));
    CLI11_PARSE(app, argc, argv);
    GDALAllRegister();
    CPLSetConfigOption("OGR_CURRENT_DATE", "2000-01-01T00:00:00.000Z");
    try {
        GDALDatasetUniquePtr in(GDALDataset::Open(input.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
        if (!in) {
            throw std::runtime_error("cannot open " + input);
        }
        OGRLayer* layer = layer_name.empty() ? in->GetLayer(0) : in->GetLayerByName(layer_name.c_str());
        if (!layer) {
            throw std::runtime_error("no layer " + layer_name + " in " + input);
        }
        const Source source = read_source(*layer);
        if (source.features.empty()) {
            throw std::runtime_error("the source layer is empty");
        }
        const double w = source.extent.MaxX - source.extent.MinX;
        const double h = source.extent.MaxY - source.extent.MinY;
        const double gap = 0.05 * std::max(w, h);
        const long long per_copy = static_cast<long long>(source.features.size());
        const long long copies = (polygons + per_copy - 1) / per_copy;
        const long long columns = static_cast<long long>(std::ceil(std::sqrt(static_cast<double>(copies))));
        const GIntBig stride = source.max_fid + 1;
        const auto start = std::chrono::steady_clock::now();
        Output out(output, format, *layer);
        long long written = 0;
        for (long long c = 0; c < copies && written < polygons; ++c) {
            const double dx = static_cast<double>(c % columns) * (w + gap);
            const double dy = static_cast<double>(c / columns) * (h + gap);
            for (const OGRFeatureUniquePtr& f : source.features) {
                if (written == polygons) {
                    break;
                }
                out.add(*f, static_cast<GIntBig>(c) * stride + f->GetFID(), dx, dy);
                ++written;
            }
        }
        out.close();
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%s: %lld features (%lld copies of %lld, %lld columns), %.1f s\n", output.c_str(), written, copies,
                    per_copy, columns, seconds);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_make_large_layer: %s\n", e.what());
        return 1;
    }
    return 0;
}
