// Where the write phase gets each feature's attributes from, measured on one layer (the choice
// the out-of-core issue asks to measure; the numbers and the decision are in bench/README.md):
//   reread_sequential  the layer read again in input order (what `trisnap snap` does: the read
//                      phase skips the attributes, the write phase reads every feature again);
//   reread_by_fid      the layer read again with GetFeature(FID), one feature at a time, in input
//                      order (drivers with random access: GeoPackage, Shapefile);
//   spool              the read phase reads the attributes too and writes them to a work file,
//                      the write phase reads that file back into OGRFeatures.
// Every pass runs on a warm page cache (a first pass reads the file once), one thread, and is
// timed alone; the spool's cost is what it adds to the read (read with attributes and the file
// written, less the read without attributes) plus reading the file back.
//   bench_attribute_source IN [--layer NAME] [--work DIR] [--json FILE]
#include <CLI/CLI.hpp>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0)
{
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

template <typename T>
void put(std::string& out, T v)
{
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T get(const char*& in)
{
    T v;
    std::memcpy(&v, in, sizeof v);
    in += sizeof v;
    return v;
}

// The fields of one feature, as a spool would keep them: a null flag, then the value by type
// (lists and other rare types as text).
void serialise(const OGRFeature& f, std::string& out)
{
    put<std::int64_t>(out, f.GetFID());
    for (int i = 0; i < f.GetFieldCount(); ++i) {
        if (!f.IsFieldSetAndNotNull(i)) {
            put<std::uint8_t>(out, 0);
            continue;
        }
        put<std::uint8_t>(out, 1);
        switch (f.GetFieldDefnRef(i)->GetType()) {
        case OFTInteger:
            put<std::int32_t>(out, f.GetFieldAsInteger(i));
            break;
        case OFTInteger64:
            put<std::int64_t>(out, f.GetFieldAsInteger64(i));
            break;
        case OFTReal:
            put<double>(out, f.GetFieldAsDouble(i));
            break;
        default: {
            const char* s = f.GetFieldAsString(i);
            const auto n = static_cast<std::uint32_t>(std::strlen(s));
            put<std::uint32_t>(out, n);
            out.append(s, n);
        }
        }
    }
}

OGRFeature* deserialise(OGRFeatureDefn* defn, const char*& in)
{
    auto* f = new OGRFeature(defn);
    f->SetFID(get<std::int64_t>(in));
    for (int i = 0; i < f->GetFieldCount(); ++i) {
        if (get<std::uint8_t>(in) == 0) {
            f->SetFieldNull(i);
            continue;
        }
        switch (f->GetFieldDefnRef(i)->GetType()) {
        case OFTInteger:
            f->SetField(i, get<std::int32_t>(in));
            break;
        case OFTInteger64:
            f->SetField(i, static_cast<GIntBig>(get<std::int64_t>(in)));
            break;
        case OFTReal:
            f->SetField(i, get<double>(in));
            break;
        default: {
            const auto n = get<std::uint32_t>(in);
            f->SetField(i, std::string(in, n).c_str());
            in += n;
        }
        }
    }
    return f;
}

struct Pass {
    std::string name;
    double seconds = 0; ///< wall
    std::uint64_t features = 0;
    double cpu = 0;     ///< process CPU seconds (the steadier figure on a shared machine)
};

double cpu_now()
{
    return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

class IgnoreFields {
public:
    IgnoreFields(OGRLayer& layer, bool ignore) : m_layer(layer)
    {
        std::vector<const char*> names;
        const OGRFeatureDefn* defn = layer.GetLayerDefn();
        for (int i = 0; ignore && i < defn->GetFieldCount(); ++i) {
            names.push_back(defn->GetFieldDefn(i)->GetNameRef());
        }
        names.push_back(nullptr);
        layer.SetIgnoredFields(names.data());
    }
    ~IgnoreFields() { m_layer.SetIgnoredFields(nullptr); }

private:
    OGRLayer& m_layer;
};

// A sequential pass; `each` sees every feature.
template <typename F>
Pass sequential(const std::string& name, OGRLayer& layer, bool fields, F each)
{
    const IgnoreFields ignore(layer, !fields);
    const auto t0 = Clock::now();
    const double c0 = cpu_now();
    Pass p{name};
    layer.ResetReading();
    while (OGRFeature* f = layer.GetNextFeature()) {
        each(*f);
        OGRFeature::DestroyFeature(f);
        ++p.features;
    }
    p.seconds = since(t0);
    p.cpu = cpu_now() - c0;
    return p;
}

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"where the write phase's attributes come from: re-read in order, by FID, or spooled"};
    std::string input, layer_name, work = std::filesystem::temp_directory_path().string(), json;
    app.add_option("IN", input)->required();
    app.add_option("--layer", layer_name);
    app.add_option("--work", work, "directory for the spool file");
    app.add_option("--json", json, "write the passes as JSON here");
    CLI11_PARSE(app, argc, argv);
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GDALDataset::Open(input.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds) {
        std::fprintf(stderr, "cannot open %s\n", input.c_str());
        return 1;
    }
    OGRLayer* layer = layer_name.empty() ? ds->GetLayer(0) : ds->GetLayerByName(layer_name.c_str());
    if (!layer) {
        std::fprintf(stderr, "no layer %s\n", layer_name.c_str());
        return 1;
    }
    std::vector<GIntBig> fids;
    sequential("warm-up", *layer, true, [&](OGRFeature& f) { fids.push_back(f.GetFID()); });
    std::vector<Pass> passes;
    passes.push_back(sequential("read_without_attributes", *layer, false, [](OGRFeature&) {}));
    const std::string spool_path = (std::filesystem::path(work) / "attributes.spool").string();
    {
        std::ofstream out(spool_path, std::ios::binary);
        std::string record;
        passes.push_back(sequential("read_with_attributes_spooled", *layer, true, [&](OGRFeature& f) {
            record.clear();
            serialise(f, record);
            put<std::uint32_t>(record, 0); // a real spool frames records; the size of a frame
            out.write(record.data(), static_cast<std::streamsize>(record.size()));
        }));
    }
    {
        const auto t0 = Clock::now();
        const double c0 = cpu_now();
        std::ifstream in(spool_path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const char* at = bytes.data();
        Pass p{"spool_read_back"};
        while (at < bytes.data() + bytes.size()) {
            OGRFeature* f = deserialise(layer->GetLayerDefn(), at);
            at += sizeof(std::uint32_t);
            OGRFeature::DestroyFeature(f);
            ++p.features;
        }
        p.seconds = since(t0);
        p.cpu = cpu_now() - c0;
        passes.push_back(p);
    }
    const auto spool_bytes = std::filesystem::file_size(spool_path);
    std::filesystem::remove(spool_path);
    passes.push_back(sequential("reread_sequential", *layer, true, [](OGRFeature&) {}));
    const bool random_access = layer->TestCapability(OLCRandomRead);
    if (!random_access) {
        // FlatGeobuf without its index, GeoJSON...: GetFeature() would scan the file each time.
        passes.push_back(Pass{"reread_by_fid", -1, 0}); // not run: printed as null
    } else {
        const auto t0 = Clock::now();
        const double c0 = cpu_now();
        Pass p{"reread_by_fid"};
        for (GIntBig fid : fids) {
            OGRFeature* f = layer->GetFeature(fid);
            if (!f) {
                std::fprintf(stderr, "GetFeature(%lld) failed: no random access here\n", static_cast<long long>(fid));
                return 1;
            }
            OGRFeature::DestroyFeature(f);
            ++p.features;
        }
        p.seconds = since(t0);
        p.cpu = cpu_now() - c0;
        passes.push_back(p);
    }
    const double spool = passes[1].seconds - passes[0].seconds + passes[2].seconds;
    const double spool_cpu = passes[1].cpu - passes[0].cpu + passes[2].cpu;
    std::printf("%-32s %10s %10s %10s\n", "pass", "wall s", "CPU s", "features");
    for (const Pass& p : passes) {
        std::printf("%-32s %10.2f %10.2f %10llu\n", p.name.c_str(), p.seconds, p.cpu,
                    static_cast<unsigned long long>(p.features));
    }
    std::printf("CPU s: reread_sequential %.2f, reread_by_fid %.2f, spool %.2f\n", passes[3].cpu, passes[4].cpu, spool_cpu);
    std::printf("\nwrite phase's attribute source:\n  reread_sequential %.2f s\n  reread_by_fid     %.2f s\n"
                "  spool             %.2f s (%.2f added to the read, %.2f to read it back; %.0f MB)\n",
                passes[3].seconds, passes[4].seconds, spool, passes[1].seconds - passes[0].seconds, passes[2].seconds,
                static_cast<double>(spool_bytes) / 1e6);
    if (!json.empty()) {
        auto number = [](double v) { return v < 0 ? std::string("null") : std::to_string(v); };
        std::ofstream out(json);
        out << "{\n  \"input\": \"" << input << "\",\n  \"features\": " << fids.size()
            << ",\n  \"random_access\": " << (random_access ? "true" : "false") << ",\n  \"spool_bytes\": " << spool_bytes
            << ",\n  \"passes\": {";
        for (std::size_t i = 0; i < passes.size(); ++i) {
            out << (i ? "," : "") << "\n    \"" << passes[i].name << "\": {\"wall_s\": " << number(passes[i].seconds)
                << ", \"cpu_s\": " << number(passes[i].seconds < 0 ? -1 : passes[i].cpu) << "}";
        }
        out << "\n  },\n  \"write_source_wall_s\": {\"reread_sequential\": " << number(passes[3].seconds)
            << ", \"reread_by_fid\": " << number(passes[4].seconds) << ", \"spool\": " << number(spool) << "},"
            << "\n  \"write_source_cpu_s\": {\"reread_sequential\": " << number(passes[3].cpu)
            << ", \"reread_by_fid\": " << number(passes[4].seconds < 0 ? -1 : passes[4].cpu) << ", \"spool\": "
            << number(spool_cpu) << "}\n}\n";
    }
    return 0;
}
