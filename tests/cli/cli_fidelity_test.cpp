// Nothing changes silently: what the output format cannot hold is a problem with FID and field
// and a warning line; what cannot be read is its own problem with GDAL's message; a NaN or
// infinite Z is reported and never spreads to a neighbour; running out of memory says so.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>

namespace trisnap::test {
namespace {
namespace fs = std::filesystem;

/// Problems of `report` with `code`, as (fid, message).
std::vector<std::pair<std::int64_t, std::string>> problems_with(const nlohmann::json& report, int code)
{
    std::vector<std::pair<std::int64_t, std::string>> out;
    for (const auto& p : report["problems"]) {
        if (p["code"] == code) {
            out.emplace_back(p["fid"].get<std::int64_t>(), p["message"].get<std::string>());
        }
    }
    return out;
}

bool has_problem(const nlohmann::json& report, int code, std::int64_t fid, const std::string& text)
{
    const auto list = problems_with(report, code);
    return std::any_of(list.begin(), list.end(), [&](const auto& p) {
        return p.first == fid && p.second.find(text) != std::string::npos;
    });
}

std::string repeated(const std::string& text, int times)
{
    std::string out;
    for (int i = 0; i < times; ++i) {
        out += text;
    }
    return out;
}

/// A GPKG layer with what a Shapefile cannot hold: a long field name, strings over 254 bytes,
/// a Real that 15 decimals round to 0, one too wide for 24 characters, a time of day.
void write_awkward_values(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference srs;
    srs.importFromEPSG(3857);
    OGRLayer* layer = ds->CreateLayer("awkward", &srs, wkbPolygon, nullptr);
    for (const auto& [name, type] : std::vector<std::pair<const char*, OGRFieldType>>{
             {"a_rather_long_field_name", OFTString}, {"label", OFTString}, {"tiny", OFTReal}, {"stamp", OFTDateTime}}) {
        OGRFieldDefn field(name, type);
        layer->CreateField(&field);
    }
    const std::vector<std::vector<std::string>> rows = {
        {"one", std::string(300, 'x'), "1e-300", "2020-01-02T03:04:05"},
        {"two", repeated("\xC3\xA9", 150), "0.25", "2020-01-02T00:00:00"}, // 150 characters, 300 bytes
        {"three", "short", "-1e300", "2021-05-06T00:00:00"},
    };
    for (std::size_t i = 0; i < rows.size(); ++i) {
        OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        for (int k = 0; k < 4; ++k) {
            f->SetField(k, rows[i][k].c_str());
        }
        const double x = 10.0 * static_cast<double>(i);
        OGRGeometry* g = nullptr;
        const std::string wkt = "POLYGON ((" + std::to_string(x) + " 0," + std::to_string(x + 5) + " 0," +
                                std::to_string(x + 5) + " 5," + std::to_string(x) + " 5," + std::to_string(x) + " 0))";
        OGRGeometryFactory::createFromWkt(wkt.c_str(), nullptr, &g);
        f->SetGeometryDirectly(g);
        f->SetFID(static_cast<GIntBig>(i + 1));
        ASSERT_EQ(layer->CreateFeature(f.get()), OGRERR_NONE);
    }
}

class CliFidelity : public ::testing::Test {
protected:
    TempDir dir;
};

TEST_F(CliFidelity, ValuesAndNamesAShapefileChangesAreProblemsAndOneWarningPerKind)
{
    const std::string in = dir.path("awkward.gpkg");
    write_awkward_values(in);
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.shp"), "--tolerance", "0.01", "--report", report});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(report);
    EXPECT_TRUE(has_problem(j, 903, 1, "field 'label': value cut to 254 bytes")) << j["problems"].dump(1);
    EXPECT_TRUE(has_problem(j, 903, 2, "field 'label': value cut to 254 bytes (300 bytes)"));
    EXPECT_TRUE(has_problem(j, 903, 1, "field 'tiny': value rounded to the 15 decimals"));
    EXPECT_TRUE(has_problem(j, 903, 3, "field 'tiny': value too wide"));
    EXPECT_TRUE(has_problem(j, 903, 1, "field 'stamp': value stored without its time of day"));
    EXPECT_TRUE(has_problem(j, 904, -1, "field 'a_rather_long_field_name' is named 'a_rather_l'"));
    EXPECT_EQ(problems_with(j, 903).size(), 5u) << "fid 2's 0.25 and fid 3's midnight are kept";
    // One line per field and kind on stderr, not one per feature.
    const auto lines = r.err_lines();
    EXPECT_EQ(lines.size(), 5u) << r.err;
    for (const std::string& line : lines) {
        EXPECT_EQ(line.rfind("trisnap: warning: ", 0), 0u) << line;
    }
    EXPECT_NE(r.err.find("field 'label': 2 values cut to 254 bytes (first FID 1; problem 903)"), std::string::npos) << r.err;
    // The report says what the file holds.
    const auto features = read_layer(dir.path("out.shp"));
    ASSERT_EQ(features.size(), 3u);
    EXPECT_EQ(features[0].fields.at("tiny"), "0");
    EXPECT_EQ(features[0].fields.at("label").size(), 254u);
}

TEST_F(CliFidelity, AFormatThatHoldsEveryValueReportsNothing)
{
    const std::string in = dir.path("awkward.gpkg");
    write_awkward_values(in);
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(read_json(report)["problems"].size(), 0u) << read_json(report)["problems"].dump(1);
    EXPECT_EQ(read_layer(dir.path("out.gpkg"))[0].fields.at("tiny"), "1e-300");
}

TEST_F(CliFidelity, AGarbageGeometryBlobIsUnreadableNotNull)
{
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbPolygon,
                  {{"POLYGON ((0 0,1 0,1 1,0 1,0 0))", {{"id", "1"}}},
                   {"POLYGON ((5 5,6 5,6 6,5 6,5 5))", {{"id", "2"}}},
                   {"POLYGON ((9 9,10 9,10 10,9 10,9 9))", {{"id", "3"}}}});
    {
        GDALDatasetUniquePtr ds(GDALDataset::Open(in.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
        ds->ExecuteSQL("UPDATE parcels SET geom = X'47500003E61000000102030405060708' WHERE fid = 2", nullptr, nullptr);
    }
    const std::string report = dir.path("r.json");
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(report);
    EXPECT_TRUE(has_problem(j, 110, 2, "GDAL: Unable to read geometry")) << j["problems"].dump(1);
    EXPECT_TRUE(problems_with(j, 107).empty()) << "not a null geometry: " << j["problems"].dump(1);
    const auto features = read_layer(dir.path("out.gpkg"));
    EXPECT_EQ(features.size(), 2u);
    EXPECT_EQ(missing_but_reported(j, features), std::vector<std::int64_t>{2});
    r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--overwrite", "--strict", "-q"});
    EXPECT_EQ(r.code, 3);
}

TEST_F(CliFidelity, AShapefileCutShortGivesUnreadableGeometries)
{
    const std::string in = dir.path("cut.shp");
    write_fixture(in, "ESRI Shapefile", "cut", 3857, wkbPolygon, snapping_fixture());
    fs::resize_file(in, fs::file_size(in) * 6 / 10);
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = read_json(report);
    const auto unreadable = problems_with(j, 110);
    ASSERT_FALSE(unreadable.empty()) << j["problems"].dump(1);
    EXPECT_NE(unreadable[0].second.find("from .shp file"), std::string::npos) << unreadable[0].second;
    EXPECT_TRUE(problems_with(j, 107).empty()) << j["problems"].dump(1);
    const auto features = read_layer(dir.path("out.gpkg"));
    EXPECT_EQ(features.size() + missing_but_reported(j, features).size(), 6u);
}

TEST_F(CliFidelity, NonFiniteZIsReportedAndDoesNotSpreadToTheNeighbour)
{
    const std::string in = dir.path("z.gpkg");
    write_fixture(in, "GPKG", "z", 3857, wkbPolygon25D,
                  {{"POLYGON Z ((0 0 5,10 0 5,10 10 5,0 10 5,0 0 5))", {{"id", "1"}}},
                   {"POLYGON Z ((10 0 5,20 0 5,20 10 5,10 10 5,10 0 5))", {{"id", "2"}}}});
    {
        GDALDatasetUniquePtr ds(GDALDataset::Open(in.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
        OGRLayer* layer = ds->GetLayer(0);
        OGRFeatureUniquePtr f(layer->GetFeature(2));
        OGRLinearRing* ring = f->GetGeometryRef()->toPolygon()->getExteriorRing();
        ring->setPoint(0, 10, 0, std::numeric_limits<double>::infinity());
        ring->setPoint(4, 10, 0, std::numeric_limits<double>::infinity());
        ASSERT_EQ(layer->SetFeature(f.get()), OGRERR_NONE);
    }
    const std::string report = dir.path("r.json");
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--report", report, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(has_problem(read_json(report), 111, 2, "2 vertices with NaN or infinite Z")) << read_json(report).dump(1);
    const auto features = read_layer(dir.path("out.gpkg"));
    ASSERT_EQ(features.size(), 2u);
    for (const ReadFeature& f : features) {
        EXPECT_EQ(f.wkt.find("inf"), std::string::npos) << f.wkt;
        EXPECT_NE(f.wkt.find("10 0 5"), std::string::npos) << "the shared vertex keeps the neighbour's z: " << f.wkt;
    }
}

TEST(CliMemory, RunningOutOfMemoryGivesTheHint)
{
    const std::string in = data_dir() + "/natural_earth/natural_earth.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    TempDir dir;
    // 230 MB of address space: the read phase fits (it fails in GDAL below about 175 MB, which
    // is a different message), the run does not (it needs about 290 MB since the 2026-11-27
    // memory work; this limit was 300 MB before, which the run then fitted in).
    const RunOutput r = run_trisnap_limited(dir, {"snap", in, dir.path("out.gpkg"), "--layer", "ne_10m_land",
                                                  "--tolerance", "1e-6", "--threads", "1"},
                                            Limits{0, 230LL << 20});
    expect_error(r, 1, "out of memory; give --memory-limit");
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
    EXPECT_EQ(leftovers(dir.path("")), std::vector<std::string>{});
}

} // namespace
} // namespace trisnap::test
