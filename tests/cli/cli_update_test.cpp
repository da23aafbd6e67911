// Writing into an existing datasource as ogr2ogr does (issue 14): --overwrite replaces only the
// output layer of a multi-layer GeoPackage, --update adds a layer, --append adds features; the
// other layers keep their features and values; a failed write (a full disk) leaves the file as
// it was; single-layer formats are replaced whole as before; the input's own file is refused.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace trisnap::test {
namespace {
namespace fs = std::filesystem;

std::string sample() { return std::string(TRISNAP_CONFIGS_DIR) + "/../data/delft_partition_sample.gpkg"; }

/// The fields, FIDs and geometries of every layer of a dataset, by layer name.
std::map<std::string, std::vector<ReadFeature>> all_layers(const std::string& path)
{
    std::map<std::string, std::vector<ReadFeature>> layers;
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    EXPECT_TRUE(ds) << path;
    for (int i = 0; ds && i < ds->GetLayerCount(); ++i) {
        const std::string name = ds->GetLayer(i)->GetName();
        layers[name] = read_layer(path, name);
    }
    return layers;
}

bool same(const std::vector<ReadFeature>& a, const std::vector<ReadFeature>& b)
{
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].fid != b[i].fid || a[i].fields != b[i].fields || a[i].wkt != b[i].wkt) {
            return false;
        }
    }
    return true;
}

class CliUpdate : public ::testing::Test {
protected:
    /// project.gpkg with four layers: roads, buildings, parcels (the snapping fixture) and water.
    std::string project()
    {
        const std::string path = dir.path("project.gpkg");
        const std::vector<FixtureFeature> all = snapping_fixture();
        write_fixture(path, "GPKG", "roads", 3857, wkbUnknown, {all[0], all[1]});
        add_layer(path, "buildings", {all[2], all[3], all[5]});
        add_layer(path, "parcels", all);
        add_layer(path, "water", {all[4]});
        return path;
    }

    /// write_fixture() into a second file, then that layer copied into `path`.
    void add_layer(const std::string& path, const std::string& name, const std::vector<FixtureFeature>& features)
    {
        const std::string one = dir.path(name + ".gpkg");
        write_fixture(one, "GPKG", name, 3857, wkbUnknown, features);
        GDALDatasetUniquePtr src(GDALDataset::Open(one.c_str(), GDAL_OF_VECTOR));
        GDALDatasetUniquePtr dst(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
        ASSERT_TRUE(src && dst);
        ASSERT_NE(dst->CopyLayer(src->GetLayer(0), name.c_str()), nullptr);
    }

    /// Every layer of `path` but `except` is as in `before`.
    void expect_others_kept(const std::map<std::string, std::vector<ReadFeature>>& before, const std::string& path,
                            const std::string& except)
    {
        const auto after = all_layers(path);
        for (const auto& [name, features] : before) {
            if (name == except) {
                continue;
            }
            ASSERT_TRUE(after.count(name)) << "layer " << name << " is gone";
            EXPECT_TRUE(same(features, after.at(name))) << "layer " << name << " changed";
        }
    }

    TempDir dir;
};

TEST_F(CliUpdate, OverwriteReplacesOnlyItsLayerOfAFourLayerGeoPackage)
{
    const std::string out = project();
    const auto before = all_layers(out);
    ASSERT_EQ(before.size(), 4u);
    ASSERT_EQ(before.at("buildings").size(), 3u);
    const RunOutput r = run_trisnap(dir, {"snap", sample(), out, "-nln", "parcels", "--tolerance", "0.01", "--overwrite"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto after = all_layers(out);
    EXPECT_EQ(after.size(), 4u);
    expect_others_kept(before, out, "parcels");
    EXPECT_EQ(after.at("parcels").size(), 260u); // the sample's, snapped: none collapses at 1 cm
    for (const ReadFeature& f : after.at("parcels")) {
        EXPECT_TRUE(f.valid) << f.fid;
    }
}

TEST_F(CliUpdate, UpdateAddsALayerAndRefusesAnExistingOne)
{
    const std::string out = project();
    const auto before = all_layers(out);
    RunOutput r = run_trisnap(dir, {"snap", sample(), out, "-nln", "parcels_snapped", "--tolerance", "0.01", "-update", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(all_layers(out).size(), 5u);
    expect_others_kept(before, out, "");
    EXPECT_EQ(read_layer(out, "parcels_snapped").size(), 260u);
    const std::string bytes = file_bytes(out);
    r = run_trisnap(dir, {"snap", sample(), out, "-nln", "water", "--tolerance", "0.01", "--update"});
    expect_error(r, 2, "has a layer 'water' already; add --overwrite to replace it, --append to add to it");
    EXPECT_TRUE(file_bytes(out) == bytes) << "the file changed";
}

TEST_F(CliUpdate, AppendAddsFeaturesAndRefusesAnotherSchema)
{
    const std::string out = project();
    const auto before = all_layers(out);
    const std::string in = dir.path("more.gpkg");
    write_fixture(in, "GPKG", "buildings", 3857, wkbUnknown, {snapping_fixture()[4]});
    RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-append", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    expect_others_kept(before, out, "buildings");
    const std::vector<ReadFeature> buildings = read_layer(out, "buildings");
    ASSERT_EQ(buildings.size(), 4u);
    EXPECT_TRUE(same({buildings.begin(), buildings.begin() + 3}, before.at("buildings")));
    EXPECT_EQ(buildings[3].fields.at("name"), "with hole");
    const std::string bytes = file_bytes(out);
    r = run_trisnap(dir, {"snap", sample(), out, "-nln", "buildings", "--tolerance", "0.01", "--append"});
    expect_error(r, 2, "(layer 'buildings'): --append: the layer has no field");
    EXPECT_TRUE(file_bytes(out) == bytes) << "the file changed";
}

TEST_F(CliUpdate, AFullDiskLeavesTheGeoPackageAsItWas)
{
    const std::string out = project();
    const auto before = all_layers(out);
    const auto limit = static_cast<long long>(fs::file_size(out)) + 16 * 1024; // the sample needs ~300 KiB more
    const RunOutput r = run_trisnap_limited(dir, {"snap", sample(), out, "-nln", "parcels", "--tolerance", "0.01",
                                                  "--overwrite", "-q"}, Limits{limit, 0});
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("OUT was left as it was"), std::string::npos) << r.err;
    // Every layer as it was, "parcels" included. (Not byte for byte: GDAL's GeoPackage driver
    // may commit its own bookkeeping, such as gpkg_ogr_contents feature counts, outside our transaction.)
    EXPECT_EQ(all_layers(out).size(), before.size());
    expect_others_kept(before, out, "");
}

TEST_F(CliUpdate, TheCollapseGuardRollsTheUpdateBack)
{
    const std::string out = project();
    const auto before = all_layers(out);
    const std::string in = dir.path("coarse.gpkg");
    write_fixture(in, "GPKG", "coarse", 3857, wkbUnknown, snapping_fixture());
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "-nln", "parcels", "--tolerance", "30", "--overwrite"});
    expect_error(r, 2, "snapping would drop");
    EXPECT_EQ(all_layers(out).size(), before.size());
    expect_others_kept(before, out, ""); // "parcels" too: its deletion was rolled back
}

TEST_F(CliUpdate, SingleLayerFormatsAreReplacedWhole)
{
    for (const std::string name : {"old.geojson", "old.shp"}) {
        const std::string out = dir.path(name);
        write_fixture(out, name == "old.shp" ? "ESRI Shapefile" : "GeoJSON", "old", 3857, wkbPolygon, snapping_fixture());
        RunOutput r = run_trisnap(dir, {"snap", sample(), out, "--tolerance", "0.01", "--update"});
        expect_error(r, 2, "holds one layer per file: --update and --append need one that holds several");
        r = run_trisnap(dir, {"snap", sample(), out, "--tolerance", "0.01", "--overwrite", "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(read_layer(out).size(), 260u) << name;
    }
}

TEST_F(CliUpdate, TheInputsOwnGeoPackageIsRefused)
{
    const std::string out = project();
    const std::string bytes = file_bytes(out);
    const RunOutput r = run_trisnap(dir, {"snap", out, out, "--layer", "parcels", "-nln", "parcels_snapped",
                                          "--tolerance", "0.01", "--update"});
    expect_error(r, 2, "output is the input");
    EXPECT_TRUE(file_bytes(out) == bytes) << "the file changed";
}

TEST_F(CliUpdate, ProblemsLayerGoesIntoTheSameGeoPackage)
{
    const std::string out = project();
    const auto before = all_layers(out);
    const RunOutput r = run_trisnap(dir, {"snap", sample(), out, "-nln", "parcels", "--tolerance", "0.01", "--overwrite",
                                          "--problems-layer", out, "--report", dir.path("r.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto after = all_layers(out);
    EXPECT_EQ(after.size(), 5u);
    expect_others_kept(before, out, "parcels");
    ASSERT_TRUE(after.count("problems"));
    EXPECT_EQ(after.at("problems").size(), read_json(dir.path("r.json"))["problems"].size());
    EXPECT_FALSE(after.at("problems").empty());
}

TEST_F(CliUpdate, ProblemsLayerIntoAnotherGeoPackageKeepsItsLayers)
{
    const std::string other = project();
    const auto before = all_layers(other);
    const std::vector<std::string> args{"snap", sample(), dir.path("out.gpkg"), "--tolerance", "0.01",
                                        "--problems-layer", other, "--update", "-q"};
    RunOutput r = run_trisnap(dir, args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(all_layers(other).size(), 5u);
    expect_others_kept(before, other, "");
    EXPECT_FALSE(read_layer(other, "problems").empty());
    fs::remove(dir.path("out.gpkg"));
    r = run_trisnap(dir, args);
    expect_error(r, 2, "has a layer 'problems' already; add --overwrite to replace it");
}

TEST_F(CliUpdate, OverwriteWithAppendIsRefused)
{
    const RunOutput r = run_trisnap(dir, {"snap", sample(), project(), "--tolerance", "0.01", "--overwrite", "--append"});
    expect_error(r, 2, "give --overwrite (replace the layer) or --append (add to it), not both");
}

} // namespace
} // namespace trisnap::test
