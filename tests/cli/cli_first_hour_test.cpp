// The gaps an audit of issue 14 ("a GIS analyst's first hour") found: output formats that undo
// the snap or reproject after it are refused; the collapse guard's pre-check runs before any
// snapping in `snap` too; progress counts say what they count; validate reads an .osm.pbf as
// snap does; several layers of one .osm.pbf; hints for ogr2ogr options trisnap does not take;
// --layer for assess and render, and footers that name only a command's own options.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <set>

namespace trisnap::test {
namespace {

std::string sample()
{
    return std::string(TRISNAP_CONFIGS_DIR) + "/../data/delft_partition_sample.gpkg";
}

std::string monaco_pbf()
{
    return data_dir() + "/osm_monaco_osrm_2020/monaco.osm.pbf";
}

/// `n` squares of side `size` degrees near Andorra (EPSG:4326), 0.001 degrees apart.
std::string wgs84_squares(const TempDir& dir, int n, double size)
{
    std::vector<FixtureFeature> features;
    for (int i = 0; i < n; ++i) {
        const double x = 1.5 + i * 0.001;
        const double y = 42.5;
        char wkt[256];
        std::snprintf(wkt, sizeof wkt, "POLYGON ((%.9f %.9f,%.9f %.9f,%.9f %.9f,%.9f %.9f,%.9f %.9f))", x, y, x + size, y,
                      x + size, y + size, x, y + size, x, y);
        features.push_back({wkt, {{"id", std::to_string(i + 1)}}});
    }
    const std::string path = dir.path("wgs84.gpkg");
    write_fixture(path, "GPKG", "squares", 4326, wkbPolygon, features);
    return path;
}

/// The --json-progress lines of a run, parsed.
std::vector<nlohmann::json> progress_lines(const RunOutput& r)
{
    std::vector<nlohmann::json> lines;
    for (const std::string& line : r.err_lines()) {
        nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        if (!j.is_discarded() && j.contains("phase")) {
            lines.push_back(std::move(j));
        }
    }
    return lines;
}

std::set<std::string> phases_of(const RunOutput& r)
{
    std::set<std::string> phases;
    for (const nlohmann::json& j : progress_lines(r)) {
        phases.insert(j["phase"].get<std::string>());
    }
    return phases;
}

/// The final --json-progress line of `phase`.
nlohmann::json final_line(const RunOutput& r, const std::string& phase)
{
    for (const nlohmann::json& j : progress_lines(r)) {
        if (j["phase"] == phase && j["finished"].get<bool>()) {
            return j;
        }
    }
    return {};
}

/// The r/w/s flags `trisnap --formats` gives `driver` ("" when it is not listed).
std::string format_flags(const std::string& formats, const std::string& driver)
{
    std::string name = driver;
    name.resize(16, ' ');
    const std::size_t at = formats.find("\n  " + name + " ");
    return at == std::string::npos ? "" : formats.substr(at + 3 + name.size() + 1, 3);
}

/// The line of `text` that contains `part` ("" when none).
std::string line_with(const std::string& text, const std::string& part)
{
    const std::size_t at = text.find(part);
    if (at == std::string::npos) {
        return "";
    }
    const std::size_t start = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
    return text.substr(start, text.find('\n', at) - start);
}

class CliFirstHour : public ::testing::Test {
protected:
    TempDir dir;
};

TEST_F(CliFirstHour, VectorTileFormatsAreRefusedBeforeAnythingIsRead)
{
    // MBTiles and MVT wrote "260 written", exit 0, and no tile at all; tiles quantise coordinates anyway.
    for (const std::string command : {"snap", "validate"}) {
        expect_error(run_trisnap(dir, {command, sample(), dir.path("x.mbtiles"), "--tolerance", "0.01"}), 2,
                     "x.mbtiles: the MBTiles format writes vector tiles: it quantises the coordinates");
        expect_error(run_trisnap(dir, {command, sample(), dir.path("tiles"), "-f", "MVT", "--tolerance", "0.01"}), 2,
                     "-f MVT: the MVT format writes vector tiles");
        expect_error(run_trisnap(dir, {command, sample(), dir.path("x.mapml"), "-f", "MapML", "--tolerance", "0.01"}), 2,
                     "the MapML format rounds the coordinates");
        EXPECT_FALSE(exists(dir.path("x.mbtiles")));
        EXPECT_FALSE(exists(dir.path("tiles")));
    }
}

TEST_F(CliFirstHour, FormatsDoesNotAdvertiseRefusedWriters)
{
    const RunOutput r = run_trisnap(dir, {"--formats"});
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* refused : {"MVT", "MBTiles", "MapML", "XLSX", "ODS", "Memory"}) {
        const std::string flags = format_flags(r.out, refused);
        ASSERT_EQ(flags.size(), 3u) << refused << " not listed:\n" << r.out;
        EXPECT_EQ(flags[1], '-') << refused << " is advertised as writable: " << line_with(r.out, "  " + std::string(refused));
    }
    EXPECT_EQ(format_flags(r.out, "GPKG"), "rw-") << r.out;
    for (const char* wgs84_only : {"KML", "LIBKML", "GPX", "GeoJSONSeq"}) {
        EXPECT_EQ(format_flags(r.out, wgs84_only)[1], 'w') << wgs84_only;
        EXPECT_NE(line_with(r.out, "\n  " + std::string(wgs84_only) + " ").find("[OUT for WGS84 layers only]"),
                  std::string::npos) << wgs84_only << ":\n" << r.out;
    }
}

TEST_F(CliFirstHour, FormatsThatStoreWgs84OnlyAreRefusedForOtherCrss)
{
    // The sample is in EPSG:28992: KML gave lon/lat, reprojected after snapping.
    for (const std::string command : {"snap", "validate"}) {
        const RunOutput kml = run_trisnap(dir, {command, sample(), dir.path("o.kml"), "-f", "KML", "--tolerance", "0.01"});
        expect_error(kml, 2, "o.kml: the KML format stores WGS84 longitude/latitude only, and the layer is in EPSG:28992");
        EXPECT_NE(kml.err.find("reproject before snapping (ogr2ogr -t_srs EPSG:4326)"), std::string::npos) << kml.err;
        EXPECT_FALSE(exists(dir.path("o.kml")));
        // .kml is LIBKML's extension first.
        expect_error(run_trisnap(dir, {command, sample(), dir.path("o.kml"), "--tolerance", "0.01"}), 2,
                     "o.kml: the LIBKML format stores WGS84 longitude/latitude only");
        expect_error(run_trisnap(dir, {command, sample(), "-", "-f", "GeoJSONSeq", "--tolerance", "0.01"}), 2,
                     "OUT - (stdout): the GeoJSONSeq format stores WGS84 longitude/latitude only");
        expect_error(run_trisnap(dir, {command, sample(), dir.path("o.json"), "--lco", "RFC7946=YES", "--tolerance", "0.01"}),
                     2, "the GeoJSON format with --lco RFC7946=YES writes WGS84 rounded to 7 decimals");
    }
    // GPX wrote metres as latitudes (a line layer, its fields as GPX extensions).
    const std::string lines = dir.path("lines.gpkg");
    write_fixture(lines, "GPKG", "roads", 3857, wkbLineString, {{"LINESTRING (0 0,100 0,100 50)", {{"id", "1"}}}});
    expect_error(run_trisnap(dir, {"snap", lines, dir.path("o.gpx"), "--dsco", "GPX_USE_EXTENSIONS=YES", "--tolerance", "0.01"}),
                 2, "o.gpx: the GPX format stores WGS84 longitude/latitude only, and the layer is in EPSG:3857");
    EXPECT_FALSE(exists(dir.path("o.gpx")));
}

TEST_F(CliFirstHour, Wgs84LayersGoToKmlAndGeoJsonSeqWithEveryDigit)
{
    const std::string in = wgs84_squares(dir, 3, 0.000123456789);
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance-m", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<ReadFeature> reference = read_layer(dir.path("o.gpkg"));
    ASSERT_EQ(reference.size(), 3u);
    r = run_trisnap(dir, {"snap", in, dir.path("o.kml"), "--tolerance-m", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_layer(dir.path("o.kml")).size(), 3u);
    // GeoJSONSeq rounded to 7 decimals by default, and gave no feature id.
    r = run_trisnap(dir, {"snap", in, "-", "-f", "GeoJSONSeq", "--tolerance-m", "0.01", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string copy = dir.path("copy.geojsonl");
    std::ofstream(copy) << r.out;
    const std::vector<ReadFeature> streamed = read_layer(copy);
    ASSERT_EQ(streamed.size(), reference.size());
    for (std::size_t i = 0; i < streamed.size(); ++i) {
        EXPECT_EQ(streamed[i].wkt, reference[i].wkt);
        EXPECT_EQ(streamed[i].fid, reference[i].fid);
    }
    EXPECT_NE(r.out.find("\"id\": 1,"), std::string::npos) << r.out.substr(0, 300);
}

TEST_F(CliFirstHour, SnapStopsOnThePreCheckBeforeSnapping)
{
    // 20 buildings of ~11 m at --tolerance 0.01 (degrees): the pre-check stops it after the read.
    const std::string in = wgs84_squares(dir, 20, 0.0001);
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--json-progress",
                                          "--progress", "never"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("trisnap: error: " + in + " (layer 'squares'): at least 20 of 20 features are smaller than "
                         "the tolerance: snapping would drop them"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("you probably meant --tolerance-m 0.01"), std::string::npos) << r.err;
    EXPECT_EQ(phases_of(r), std::set<std::string>{"plan"}) << "a phase after the read ran:\n" << r.err;
    EXPECT_FALSE(exists(dir.path("o.gpkg")));
    // To stdout: not even the stream's header is out.
    const RunOutput streamed = run_trisnap(dir, {"snap", in, "-", "--tolerance", "0.01"});
    EXPECT_EQ(streamed.code, 2) << streamed.err;
    EXPECT_EQ(streamed.out, "");
}

TEST_F(CliFirstHour, AndorraAtOneHundredthOfADegreeStopsBeforeSnapping)
{
    // It snapped for 115 s before the guard stopped it; validate stopped the same case at once.
    const std::string in = data_dir() + "/snapoly_andorra/andorra.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    const RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--json-progress",
                                          "--progress", "never"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("features are smaller than the tolerance: snapping would drop them"), std::string::npos) << r.err;
    EXPECT_EQ(phases_of(r).count("snap"), 0u) << r.err;
    EXPECT_EQ(phases_of(r).count("spool"), 0u) << r.err;
    const RunOutput v = run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(v.code, 2) << v.err;
    EXPECT_EQ(line_with(v.err, "trisnap: error:"), line_with(r.err, "trisnap: error:")) << "one pre-check, one message";
}

TEST_F(CliFirstHour, ProgressCountsWhatItSays)
{
    // --force on a total collapse: the write bar said 260/260 and 0 were written.
    RunOutput r = run_trisnap(dir, {"snap", sample(), dir.path("o.gpkg"), "--tolerance", "1000", "--force",
                                    "--json-progress", "--progress", "never", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json write = final_line(r, "write");
    EXPECT_EQ(write["unit"], "features written") << write;
    EXPECT_EQ(write["done"], 0) << write;
    EXPECT_EQ(write["total"], 260) << write;
    // The spool reads each feature twice: counted once (it said "520/520 feature reads").
    const nlohmann::json spool = final_line(r, "spool");
    EXPECT_EQ(spool["unit"], "features") << spool;
    EXPECT_EQ(spool["total"], 260) << spool;
    // The stitch phase counts the tiles whose seams it checks, and ends with a total.
    const nlohmann::json stitch = final_line(r, "stitch");
    EXPECT_EQ(stitch["unit"], "tiles") << stitch;
    EXPECT_EQ(stitch["done"], stitch["total"]) << stitch;

    r = run_trisnap(dir, {"snap", sample(), dir.path("p.gpkg"), "--tolerance", "0.01", "--json-progress", "--progress",
                          "never", "--report", dir.path("p.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    write = final_line(r, "write");
    EXPECT_EQ(write["done"], read_json(dir.path("p.json"))["counts"]["written"]) << write;
}

TEST_F(CliFirstHour, ValidateReadsAnOsmFileAsSnapDoes)
{
    const std::string in = monaco_pbf();
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    // validate said "ok" here, and snap exited 1.
    for (const std::string command : {"validate", "snap"}) {
        expect_error(run_trisnap(dir, {command, in, dir.path("o.gpkg"), "--layer", "multipolygons", "--tolerance-m",
                                       "0.05", "--where", "1=0"}),
                     1, "no feature matches --where/--bbox: nothing to snap");
    }
    // A tolerance that collapses every feature (1 degree): validate said "ok".
    const RunOutput v = run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--layer", "multipolygons", "--tolerance", "1"});
    EXPECT_EQ(v.code, 2) << v.err;
    EXPECT_NE(v.err.find("features are smaller than the tolerance"), std::string::npos) << v.err;
    const RunOutput s = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--layer", "multipolygons", "--tolerance", "1",
                                          "--json-progress", "--progress", "never"});
    EXPECT_EQ(s.code, 2) << s.err;
    EXPECT_EQ(phases_of(s), std::set<std::string>{"plan"}) << s.err;
    // The counts are read, not guessed from the file's size.
    const RunOutput ok =
        run_trisnap(dir, {"validate", in, dir.path("o.gpkg"), "--layer", "multipolygons", "--tolerance-m", "0.05"});
    ASSERT_EQ(ok.code, 0) << ok.err;
    EXPECT_EQ(ok.out.find("from the input's size"), std::string::npos) << ok.out;
    EXPECT_EQ(ok.out.find("features unknown until read"), std::string::npos) << ok.out;
    const RunOutput run = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--layer", "multipolygons", "--tolerance-m",
                                            "0.05", "--report", dir.path("r.json"), "-q"});
    ASSERT_EQ(run.code, 0) << run.err;
    const nlohmann::json counts = read_json(dir.path("r.json"))["counts"];
    EXPECT_NE(ok.out.find(", " + std::to_string(counts["input"].get<int>()) + " features, CRS"), std::string::npos)
        << ok.out;
}

TEST_F(CliFirstHour, SeveralLayersOfAnOsmFile)
{
    const std::string in = monaco_pbf();
    if (!exists(in)) {
        GTEST_SKIP() << "data set absent: " << in;
    }
    const std::string out = dir.path("monaco.gpkg");
    const RunOutput r = run_trisnap(dir, {"snap", in, out, "--layer", "multipolygons", "--layer", "lines",
                                          "--tolerance-m", "0.05", "--report", dir.path("r.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = read_json(dir.path("r.json"));
    ASSERT_EQ(j["layers"].size(), 2u) << j.dump(1);
    // Each layer read whole, as a run of that layer alone reads it.
    for (const std::string layer : {"multipolygons", "lines"}) {
        const RunOutput alone = run_trisnap(dir, {"snap", in, dir.path(layer + ".gpkg"), "--layer", layer,
                                                  "--tolerance-m", "0.05", "--report", dir.path(layer + ".json"), "-q"});
        ASSERT_EQ(alone.code, 0) << alone.err;
        const nlohmann::json one = read_json(dir.path(layer + ".json"));
        const nlohmann::json& both = j["layers"][layer == "lines" ? 1 : 0];
        EXPECT_EQ(both["counts"]["input"], one["counts"]["input"]) << layer;
        EXPECT_GT(both["counts"]["input"].get<int>(), 100) << layer;
        EXPECT_EQ(read_layer(out, layer).size(), both["counts"]["written"].get<std::size_t>()) << layer;
    }
}

TEST_F(CliFirstHour, Ogr2ogrOptionsTrisnapDoesNotTakeSayWhatToDo)
{
    const std::string in = sample();
    const std::string out = dir.path("o.gpkg");
    auto error_for = [&](std::vector<std::string> extra) {
        std::vector<std::string> args{"snap", in, out, "--tolerance", "0.01"};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_trisnap(dir, args);
    };
    for (const char* option : {"-t_srs", "-s_srs"}) {
        expect_error(error_for({option, "EPSG:4326"}), 2,
                     "unknown option " + std::string(option) + " for trisnap snap: trisnap does not reproject");
    }
    expect_error(error_for({"-a_srs", "EPSG:4326"}), 2, "trisnap does not assign a CRS");
    expect_error(error_for({"-clipsrc", "0", "0", "1", "1"}), 2, "trisnap does not clip: --bbox (-spat)");
    const RunOutput sql = error_for({"-sql", "SELECT * FROM x"});
    expect_error(sql, 2, "trisnap reads a layer, not an SQL result: choose features with --where");
    EXPECT_EQ(sql.err.find("-q?"), std::string::npos) << sql.err;
    const RunOutput nlt = error_for({"-nlt", "MULTIPOLYGON"});
    expect_error(nlt, 2, "trisnap keeps the input's geometry types");
    EXPECT_EQ(nlt.err.find("--nln?"), std::string::npos) << nlt.err;
    expect_error(run_trisnap(dir, {"snap", in, out, "--tol", "0.01"}), 2,
                 "unknown option --tol for trisnap snap; did you mean --tolerance?");
}

TEST_F(CliFirstHour, AssessAndRenderTakeLayerForBothFiles)
{
    const std::string in = write_snapping_gpkg(dir);
    const std::string out = dir.path("out.gpkg");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, out, "--tolerance", "0.01", "-q"}).code, 0);
    RunOutput r = run_trisnap(dir, {"assess", in, out, "--layer", "parcels", "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
    r = run_trisnap(dir, {"render", in, out, "--layer", "parcels", "-o", dir.path("p.svg")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(exists(dir.path("p.svg")));
    expect_error(run_trisnap(dir, {"assess", in, out, "--layer", "parcels", "--layer-b", "parcels", "--tolerance", "0.01"}),
                 2, "--layer parcels names the layer of both files; give it alone, or --layer-a and --layer-b");
    // Named differently in the two files: --layer is ambiguous there, and the error says which file lacks it.
    const std::string renamed = dir.path("renamed.gpkg");
    ASSERT_EQ(run_trisnap(dir, {"snap", in, renamed, "--tolerance", "0.01", "-nln", "snapped", "-q"}).code, 0);
    expect_error(run_trisnap(dir, {"assess", in, renamed, "--layer", "parcels", "--tolerance", "0.01"}), 2,
                 "--layer parcels: SNAPPED " + renamed + " has no layer of that name (layers: snapped");
    r = run_trisnap(dir, {"assess", in, renamed, "--layer-a", "parcels", "--layer-b", "snapped", "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(CliFirstHour, HelpFootersNameOnlyTheCommandsOwnOptions)
{
    for (const std::string command : {"assess", "render", "info", "problems"}) {
        const RunOutput r = run_trisnap(dir, {command, "--help"});
        ASSERT_EQ(r.code, 0) << r.err;
        for (const char* foreign : {"-nln", "--strict", "-skipfailures", "--settings"}) {
            const std::string footer = r.out.substr(r.out.find("--config KEY VALUE"));
            EXPECT_EQ(footer.find(foreign), std::string::npos) << command << " --help footer mentions " << foreign
                                                               << ":\n" << footer;
        }
    }
    const RunOutput snap = run_trisnap(dir, {"snap", "--help"});
    EXPECT_NE(snap.out.find("-nln, -lco, -dsco"), std::string::npos) << snap.out;
    EXPECT_NE(snap.out.find("--strict was given"), std::string::npos) << snap.out;
}

TEST_F(CliFirstHour, TheWarningAndTheGuardGiveOneFigureForDegrees)
{
    // The warning said ">= 1.1e+03 m" and the guard "about 820 m here" for the same 0.01 degrees.
    const RunOutput r = run_trisnap(dir, {"snap", wgs84_squares(dir, 20, 0.0001), dir.path("o.gpkg"), "--tolerance", "0.01"});
    EXPECT_EQ(r.code, 2) << r.err;
    const std::vector<std::string> lines = r.err_lines();
    ASSERT_EQ(lines.size(), 2u) << r.err;
    const std::string figure = "(0.01 degrees, about 821 m here)";
    EXPECT_NE(lines[0].find("trisnap: warning: --tolerance 0.01 is in degrees on this geographic CRS " + figure),
              std::string::npos) << lines[0];
    EXPECT_NE(lines[1].find(figure), std::string::npos) << lines[1];
}

} // namespace
} // namespace trisnap::test
