// Round trip per format: every field value of every kept feature equal, valid geometry, the
// same CRS, every input feature in OUT or in the report, and identical bytes on a second run.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace trisnap::test {
namespace {

struct Format {
    const char* ext;
    bool keeps_layer_name; ///< Shapefile names its layer after the file
    std::vector<const char*> files; ///< every file the format writes, for byte comparison
};

std::vector<FixtureFeature> mixed_fixture()
{
    std::vector<FixtureFeature> features = snapping_fixture();
    features.push_back({"LINESTRING (0 -1,10 -1.004,20 -1)", {{"id", "7"}, {"name", "line"}}});
    features.push_back({"POINT (5 5)", {{"id", "8"}, {"name", "point"}}});
    return features;
}

std::map<std::int64_t, const ReadFeature*> by_fid(const std::vector<ReadFeature>& features)
{
    std::map<std::int64_t, const ReadFeature*> out;
    for (const ReadFeature& f : features) out[f.fid] = &f;
    return out;
}

std::int64_t input_fid(const ReadFeature& out)
{
    auto it = out.fields.find("orig_fid");
    return it == out.fields.end() ? out.fid : std::stoll(it->second);
}

/// The independent checks shared by all round trips.
void check_round_trip(const std::vector<ReadFeature>& input, const std::vector<ReadFeature>& output,
                      const nlohmann::json& report)
{
    const auto inputs = by_fid(input);
    std::set<std::int64_t> seen;
    for (const ReadFeature& out : output) {
        const std::int64_t fid = input_fid(out);
        ASSERT_TRUE(inputs.count(fid)) << "output feature with unknown input FID " << fid;
        EXPECT_TRUE(seen.insert(fid).second) << "FID " << fid << " written twice";
        for (const auto& [name, value] : inputs.at(fid)->fields) {
            ASSERT_TRUE(out.fields.count(name)) << "field " << name << " missing";
            // FlatGeobuf has no date-only type: GDAL writes dates as midnight date-times.
            const std::string& got = out.fields.at(name);
            if (got != value + " 00:00:00") {
                EXPECT_EQ(got, value) << "FID " << fid << " field " << name;
            }
        }
        EXPECT_TRUE(out.valid) << "FID " << fid << " invalid: " << out.wkt;
    }
    EXPECT_EQ(output.size() + missing_but_reported(report, output).size(), input.size())
        << "every input feature must be in OUT or in the report";
    EXPECT_EQ(report["counts"]["input"].get<std::size_t>(), input.size());
    EXPECT_EQ(report["counts"]["written"].get<std::size_t>(), output.size());
}

bool same_crs(const std::string& a, const std::string& b, const std::string& layer_a)
{
    GDALDatasetUniquePtr da(GDALDataset::Open(a.c_str(), GDAL_OF_VECTOR));
    GDALDatasetUniquePtr db(GDALDataset::Open(b.c_str(), GDAL_OF_VECTOR));
    const OGRSpatialReference* sa = da->GetLayerByName(layer_a.c_str())->GetSpatialRef();
    const OGRSpatialReference* sb = db->GetLayer(0)->GetSpatialRef();
    return sa && sb && sa->IsSame(sb);
}

class RoundTrip : public ::testing::TestWithParam<Format> {};

TEST_P(RoundTrip, FieldsValidityAccountingAndBytes)
{
    const Format& format = GetParam();
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, mixed_fixture());
    const std::string out = dir.path(std::string("out.") + format.ext);
    const std::string report = dir.path("report.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("8 features in"), std::string::npos) << r.out;
    const auto output = read_layer(out);
    check_round_trip(read_layer(in, "parcels"), output, read_json(report));
    const auto point = std::find_if(output.begin(), output.end(), [](const ReadFeature& f) {
        return f.fields.count("name") && f.fields.at("name") == "point";
    });
    if (std::string(format.ext) != "shp") { // a Shapefile of polygons refuses the point (reported)
        ASSERT_NE(point, output.end());
        EXPECT_EQ(point->wkt, "POINT (5 5)") << "a point passes through with its geometry";
    }
    EXPECT_TRUE(same_crs(in, out, "parcels"));
    if (format.keeps_layer_name) {
        GDALDatasetUniquePtr ds(GDALDataset::Open(out.c_str(), GDAL_OF_VECTOR));
        EXPECT_NE(ds->GetLayerByName("parcels"), nullptr);
    }
    const std::string again = dir.path(std::string("again.") + format.ext);
    ASSERT_EQ(run_trisnap(dir, {"snap", in, again, "--tolerance", "0.01", "--threads", "1", "-q"}).code, 0);
    for (const char* ext : format.files)
        EXPECT_EQ(file_bytes(dir.path(std::string("out.") + ext)), file_bytes(dir.path(std::string("again.") + ext)))
            << "." << ext << " differs between two runs";
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip,
                         ::testing::Values(Format{"gpkg", true, {"gpkg"}}, Format{"shp", false, {"shp", "shx", "dbf", "prj"}},
                                           Format{"fgb", true, {"fgb"}}, Format{"geojson", true, {"geojson"}}),
                         [](const auto& info) { return std::string(info.param.ext); });

// Every feature snapped: the write phase reads the input again without its geometries (none
// passes through); every attribute still comes back.
TEST(RoundTripOptions, AttributesWhenEveryFeatureIsSnapped)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    const std::string out = dir.path("out.gpkg");
    const std::string report = dir.path("report.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto output = read_layer(out);
    ASSERT_FALSE(output.empty());
    check_round_trip(read_layer(in, "parcels"), output, read_json(report));
    for (const ReadFeature& f : output) {
        EXPECT_NE(f.wkt.find("POLYGON ("), std::string::npos) << f.wkt;
    }
}

TEST(RoundTripOptions, NewLayerNameAndFormatFlag)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    const std::string out = dir.path("renamed.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-f", "GPKG", "-nln", "snapped",
                                          "--lco", "DESCRIPTION=test", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(read_layer(out, "snapped").empty());
}

TEST(RoundTripOsm, MultipolygonsAndLinesFromPbf)
{
    const std::string pbf = data_dir() + "/osm_small_extracts/andorra_graphhopper_2013.osm.pbf";
    if (!exists(pbf)) GTEST_SKIP() << "data set absent: " << pbf;
    TempDir dir;
    const struct {
        const char* layer;
        const char* ext;
    } cases[] = {{"multipolygons", "gpkg"}, {"lines", "fgb"}};
    // Central Andorra la Vella: a few hundred features keep the test fast and cover --bbox.
    const std::vector<double> bbox{1.50, 42.49, 1.54, 42.52};
    for (const auto& c : cases) {
        const std::string out = dir.path(std::string(c.layer) + "." + c.ext);
        const std::string report = dir.path(std::string(c.layer) + ".json");
        const RunOutput r = run_trisnap(dir, {"snap", pbf, out, "--layer", c.layer, "--tolerance-m", "0.01",
                                              "--bbox", "1.50,42.49,1.54,42.52", "--report", report});
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        const auto input = read_layer(pbf, c.layer, bbox);
        EXPECT_GT(input.size(), 50u);
        check_round_trip(input, read_layer(out), read_json(report));
    }
}

} // namespace
} // namespace trisnap::test
