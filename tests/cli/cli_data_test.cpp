// Every GPKG layer in ../shared/data at 1 cm (degrees at the layer's latitude on a geographic
// CRS): exit 0, then an independent check of validity, attribute equality and accounting.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace trisnap::test {
namespace {

struct DataLayer {
    std::string file;  ///< relative to the data directory
    std::string layer;
};

std::vector<DataLayer> data_layers()
{
    std::vector<DataLayer> out;
    const std::filesystem::path root(data_dir());
    if (!std::filesystem::is_directory(root)) return out;
    GDALAllRegister();
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
        if (entry.path().extension() == ".gpkg") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        GDALDatasetUniquePtr ds(GDALDataset::Open(file.c_str(), GDAL_OF_VECTOR));
        if (!ds) continue;
        for (OGRLayer* layer : ds->GetLayers())
            out.push_back({std::filesystem::relative(file, root).string(), layer->GetName()});
    }
    return out;
}

void PrintTo(const DataLayer& d, std::ostream* os) { *os << d.file << ":" << d.layer; }

class DataLayers : public ::testing::TestWithParam<DataLayer> {};

TEST_P(DataLayers, SnapsAtOneCentimetre)
{
    const DataLayer& d = GetParam();
    const std::string in = data_dir() + "/" + d.file;
    if (!exists(in)) GTEST_SKIP() << "data set absent: " << in;
    TempDir dir;
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("report.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--layer", d.layer, "--tolerance-m", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const auto input = read_layer(in, d.layer);
    const auto output = read_layer(out);
    const nlohmann::json j = read_json(report);
    std::map<std::int64_t, const ReadFeature*> inputs;
    for (const ReadFeature& f : input) inputs[f.fid] = &f;
    for (const ReadFeature& o : output) {
        ASSERT_TRUE(inputs.count(o.fid)) << "unknown FID " << o.fid;
        for (const auto& [name, value] : inputs[o.fid]->fields) EXPECT_EQ(o.fields.at(name), value) << o.fid << " " << name;
        EXPECT_TRUE(o.valid) << d.file << ":" << d.layer << " FID " << o.fid << " invalid";
    }
    EXPECT_EQ(output.size() + missing_but_reported(j, output).size(), input.size());
}

INSTANTIATE_TEST_SUITE_P(SharedData, DataLayers, ::testing::ValuesIn(data_layers()), [](const auto& info) {
    std::string name = info.param.file + "_" + info.param.layer;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
});
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(DataLayers);

} // namespace
} // namespace trisnap::test
