// ogr2ogr habits: its one-dash spellings, GDAL's --config KEY VALUE, open and creation options,
// -select, OUT "-" on stdout, FlatGeobuf in input order, connection strings as sources.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace trisnap::test {
namespace {

class CliOgr2ogr : public ::testing::Test {
protected:
    std::string fixture(const std::string& name = "in.gpkg") { return write_snapping_gpkg(dir, name); }

    TempDir dir;
};

std::string square_wkt(int x, int y)
{
    const std::string x0 = std::to_string(x);
    const std::string x1 = std::to_string(x + 5);
    const std::string y0 = std::to_string(y);
    const std::string y1 = std::to_string(y + 5);
    return "POLYGON ((" + x0 + " " + y0 + "," + x1 + " " + y0 + "," + x1 + " " + y1 + "," + x0 + " " + y1 + "," + x0 +
           " " + y0 + "))";
}

std::vector<std::string> field_names(const ReadFeature& feature)
{
    std::vector<std::string> names;
    for (const auto& [name, value] : feature.fields) {
        names.push_back(name);
    }
    return names;
}

TEST_F(CliOgr2ogr, OneDashSpellingsWork)
{
    const std::string out = dir.path("out.gpkg");
    std::ofstream(out) << "replaced by -overwrite";
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), out, "--tolerance", "0.01", "-where", "id <= 3", "-spat",
                                          "-1", "-1", "25", "25", "-select", "id,name", "-overwrite", "-nln", "renamed",
                                          "-lco", "DESCRIPTION=d", "-skipfailures", "-progress"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("100%"), std::string::npos) << "-progress draws the bar even off a terminal: " << r.err;
    const std::vector<ReadFeature> features = read_layer(out, "renamed");
    ASSERT_EQ(features.size(), 3u); // ids 1-3 lie in the box and match the filter
    for (const ReadFeature& f : features) {
        EXPECT_EQ(field_names(f), (std::vector<std::string>{"id", "name"}));
        EXPECT_LE(std::stoi(f.fields.at("id")), 3);
    }
}

TEST_F(CliOgr2ogr, SpatNeedsFourNumbersAndSelectKnownFields)
{
    RunOutput r = run_trisnap(dir, {"snap", fixture(), dir.path("o.gpkg"), "--tolerance", "1", "-spat", "1", "2", "3"});
    EXPECT_EQ(r.code, 2);
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("-spat needs four numbers"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"validate", fixture(), dir.path("o.gpkg"), "--tolerance", "1", "-select", "id,nope"});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "trisnap: error: --select: no field 'nope' in the input; fields: id, big, area, name, day\n");
}

TEST_F(CliOgr2ogr, GdalConfigKeyValueIsGdals)
{
    // GeoPackage stamps OGR_CURRENT_DATE into gpkg_contents.last_change.
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"--config", "OGR_CURRENT_DATE", "2011-02-03T04:05:06Z", "snap", fixture(), out,
                                          "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    GDALDatasetUniquePtr ds(GDALDataset::Open(out.c_str(), GDAL_OF_VECTOR));
    ASSERT_TRUE(ds);
    OGRLayer* sql = ds->ExecuteSQL("SELECT last_change FROM gpkg_contents", nullptr, nullptr);
    ASSERT_NE(sql, nullptr);
    OGRFeatureUniquePtr row(sql->GetNextFeature());
    ASSERT_TRUE(row);
    EXPECT_EQ(std::string(row->GetFieldAsString(0)).substr(0, 19), "2011/02/03 04:05:06"); // not our 2000-01-01
    ds->ReleaseResultSet(sql);
}

TEST_F(CliOgr2ogr, GdalConfigKeyEqualsValueAfterTheCommand)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), out, "--tolerance", "0.01", "--config",
                                          "OGR_CURRENT_DATE=2012-03-04T05:06:07Z", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(file_bytes(out).find("2012-03-04T05:06:07"), std::string::npos);
}

TEST_F(CliOgr2ogr, SkipfailuresIsWhatTrisnapAlwaysDoes)
{
    // A Shapefile takes one geometry type: the line is refused by the driver (902), the run goes on.
    const std::string in = dir.path("mixed.gpkg");
    write_fixture(in, "GPKG", "mixed", 3857, wkbUnknown,
                  {{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "1"}}}, {"LINESTRING (5 5,6 6)", {{"id", "2"}}},
                   {"POLYGON ((2 0,3 0,3 1,2 1,2 0))", {{"id", "3"}}}});
    std::string bytes[2];
    for (int i = 0; i < 2; ++i) {
        const std::string out = dir.path("out" + std::to_string(i) + ".shp");
        std::vector<std::string> args = {"snap", in, out, "--tolerance", "0.01", "--report", dir.path("r.json"), "-q"};
        if (i == 1) {
            args.push_back("-skipfailures");
        }
        const RunOutput r = run_trisnap(dir, args);
        ASSERT_EQ(r.code, 0) << r.err;
        const nlohmann::json j = read_json(dir.path("r.json"));
        ASSERT_EQ(j["problems"].size(), 1u) << j.dump(1);
        EXPECT_EQ(j["problems"][0]["code"], 902);
        EXPECT_EQ(j["problems"][0]["fid"], 2);
        EXPECT_EQ(read_layer(out).size(), 2u);
        bytes[i] = file_bytes(out);
    }
    EXPECT_EQ(bytes[0], bytes[1]) << "-skipfailures changes nothing";
    const RunOutput strict = run_trisnap(dir, {"snap", in, dir.path("s.shp"), "--tolerance", "0.01", "-skipfailures",
                                               "--strict", "-q"});
    EXPECT_EQ(strict.code, 3);
}

TEST_F(CliOgr2ogr, ConfigFileStillMeansSettings)
{
    const std::string file = dir.path("s.toml");
    std::ofstream(file) << "[snap]\ntolerance = 0.5\n";
    for (const char* flag : {"--config", "--settings"}) {
        const RunOutput r = run_trisnap(dir, {"snap", flag, file, "--print-config"});
        EXPECT_EQ(r.code, 0) << flag << ": " << r.err;
        EXPECT_NE(r.out.find("tolerance = 0.5\n"), std::string::npos) << flag << ": " << r.out;
    }
    const RunOutput r = run_trisnap(dir, {"snap", "--print-config", "--config", "LONELY_KEY"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--config LONELY_KEY: no value"), std::string::npos) << r.err;
}

TEST_F(CliOgr2ogr, OpenOptionsReachTheDriver)
{
    const std::string in = dir.path("nested.geojson");
    std::ofstream(in) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"a": {"b": 7}},
        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]}}]})";
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-oo", "FLATTEN_NESTED_ATTRIBUTES=YES", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<ReadFeature> features = read_layer(out);
    ASSERT_EQ(features.size(), 1u);
    EXPECT_EQ(features[0].fields.count("a"), 0u);
    EXPECT_EQ(features[0].fields.at("a_b"), "7");
}

TEST_F(CliOgr2ogr, DatasetCreationOptionsReachTheDriver)
{
    const std::string out = dir.path("out.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), out, "--tolerance", "0.01", "-dsco", "VERSION=1.0", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(file_bytes(out).substr(68, 4), "GP10"); // the SQLite application_id of GeoPackage 1.0
    const RunOutput bad = run_trisnap(dir, {"validate", fixture(), out, "--tolerance", "0.01", "--dsco", "VERSION"});
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--dsco 'VERSION': expected KEY=VALUE"), std::string::npos) << bad.err;
}

TEST_F(CliOgr2ogr, DashStreamsGeoJsonToStdout)
{
    const RunOutput r = run_trisnap(dir, {"snap", fixture(), "-", "--tolerance", "0.01"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << "stdout is not GeoJSON: " << r.out.substr(0, 200);
    EXPECT_EQ(j["type"], "FeatureCollection");
    EXPECT_EQ(j["features"].size(), 5u); // the 0.005 square collapses at 0.01
    EXPECT_NE(r.err.find("6 features in, 5 written"), std::string::npos) << "the summary goes to stderr: " << r.err;
    EXPECT_FALSE(exists(dir.path("-")));
}

TEST_F(CliOgr2ogr, DashWithFlatGeobufAndRefusedWithGeoPackage)
{
    const std::string in = fixture();
    RunOutput r = run_trisnap(dir, {"snap", in, "-", "-f", "FlatGeobuf", "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string copy = dir.path("copy.fgb");
    std::ofstream(copy, std::ios::binary) << r.out;
    EXPECT_EQ(read_layer(copy).size(), 5u);
    r = run_trisnap(dir, {"snap", in, "-", "-f", "GPKG", "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("the GPKG driver cannot stream"), std::string::npos) << r.err;
}

TEST_F(CliOgr2ogr, FlatGeobufKeepsInputOrder)
{
    // Squares in an order a Hilbert curve (GDAL's FlatGeobuf spatial index) would change.
    std::vector<FixtureFeature> features;
    for (int i = 0; i < 40; ++i) {
        const int x = (i * 17) % 40 * 10;
        const int y = (i * 7) % 13 * 10;
        features.push_back({square_wkt(x, y), {{"id", std::to_string(i)}}});
    }
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "squares", 3857, wkbPolygon, features);
    const std::string out = dir.path("out.fgb");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<ReadFeature> written = read_layer(out);
    ASSERT_EQ(written.size(), features.size());
    for (std::size_t i = 0; i < written.size(); ++i) {
        EXPECT_EQ(written[i].fields.at("id"), std::to_string(i)) << "feature " << i << " moved";
    }
}

TEST_F(CliOgr2ogr, ConnectionStringsAreSources)
{
    RunOutput r = run_trisnap(dir, {"snap", "PG:dbname=trisnap_no_such_database host=/nonexistent", dir.path("o.gpkg"),
                                    "--tolerance", "1"});
    EXPECT_EQ(r.code, 1);
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_EQ(r.err.find("no such file or directory"), std::string::npos) << r.err;
    const std::string zip = dir.path("in.zip");
    write_fixture("/vsizip/" + zip + "/in.geojson", "GeoJSON", "in", 3857, wkbUnknown, snapping_fixture());
    r = run_trisnap(dir, {"snap", "/vsizip/" + zip + "/in.geojson", dir.path("o.gpkg"), "--tolerance", "0.01", "-q"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_layer(dir.path("o.gpkg")).size(), 5u);
}

} // namespace
} // namespace trisnap::test
