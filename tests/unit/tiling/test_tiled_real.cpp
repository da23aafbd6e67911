// Tiled snapping on real layers from ../shared/data: the stitched output holds the contract,
// a planar partition stays one, and every feature equals the untiled run's, bit for bit (the
// contract: identical output for any tiling).
// Small layers run by default (label unit); big ones under `slow`. Each prints a [tiles] line.
#include "ogr_layer_reader.hpp"
#include "test_data.hpp"
#include "tiled_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

namespace trisnap {
namespace {

struct TiledCase {
    std::string name;
    const char* file;
    const char* layer;
    double tolerance;
    double tile_size; ///< 0: balanced with `budget`
    std::size_t budget = 100000;
    bool partition = false;
    int growth = 0; ///< --halo-max-growth; > 0 must see the cascade test fire on this case
    /// Features the engine may flag (as measured untiled and tiled when the bound came in).
    std::size_t max_flagged = 0;
    /// Shared boundaries the checker finds lost and the run reports lost (210), tiled and untiled
    /// alike: pinned at their count so that they can neither grow nor hide. Unreported losses
    /// break the contract.
    std::size_t lost_reported = 0;
};

std::string case_name(const ::testing::TestParamInfo<TiledCase>& info) { return info.param.name; }

std::ostream& operator<<(std::ostream& os, const TiledCase& c)
{
    return os << c.file << ":" << c.layer << " t=" << c.tolerance << " tile " << c.tile_size << " budget " << c.budget;
}

void run_case(const TiledCase& c)
{
    const auto path = shared_data(c.file);
    if (!path) GTEST_SKIP() << "data set absent: " << TRISNAP_SHARED_DATA << "/" << c.file;
    const LayerData data = read_ogr_layer(*path, c.layer);
    ASSERT_FALSE(data.features.empty());
    const SnapOptions o = options_at(c.tolerance);
    stitch::TilingOptions tiling = tiles_of(c.tile_size);
    tiling.plan.vertex_budget = c.budget;
    tiling.max_growth = c.growth;
    const SnapResult untiled = snap(data.features, o);
    const TiledRun run = tiled_and_check(data.features, o, tiling, c.max_flagged);
    const auto diff = differing(untiled, run.tiled.result);
    const std::size_t n = data.features.size();
    std::cout << "[tiles] " << c.file << ":" << c.layer << " t=" << c.tolerance << " tiles " << run.tiled.stitch.tiles
              << " (plan " << run.tiled.stitch.leaves << ", seam merges " << run.tiled.stitch.seam_merges
              << ", halo growths " << run.tiled.stitch.halo_growths << "), assembled " << run.tiled.stitch.assembled_features
              << ", identical " << n - diff.size() << "/" << n << "\n";
    EXPECT_EQ(run.report.n_shared_lost_reported, c.lost_reported) << run.report.summary();
    EXPECT_TRUE(contract_holds(run.report, c.tolerance)) << run.report.summary();
    EXPECT_EQ(run.tiled.result.features.size(), n);
    EXPECT_EQ(diff.size(), 0u) << diff.size() << " features differ from the untiled run, first id "
                               << (diff.empty() ? 0 : diff.front());
    EXPECT_EQ(problems_without_seams(untiled.problems), problems_without_seams(run.tiled.result.problems));
    EXPECT_GT(run.tiled.stitch.leaves, 1u) << "the case should cut the layer";
    if (c.growth > 0) {
        EXPECT_GT(run.tiled.stitch.halo_growths, 0u) << "the cascade test should fire here";
        for (const auto& tile : run.tiled.tiles) EXPECT_LE(tile.growths, c.growth);
    }
    if (c.partition) {
        EXPECT_EQ(run.report.n_overlaps_new, 0u) << run.report.summary();
        EXPECT_EQ(run.report.n_shared_lost, 0u) << run.report.summary();
    }
}

class TiledRealData : public ::testing::TestWithParam<TiledCase> {};
class TiledRealDataSlow : public ::testing::TestWithParam<TiledCase> {};
TEST_P(TiledRealData, ContractAndInvariance) { run_case(GetParam()); }
TEST_P(TiledRealDataSlow, ContractAndInvariance) { run_case(GetParam()); }

const char* bgt = "bgt_delft_3dfier/bgt_delft.gpkg";

INSTANTIATE_TEST_SUITE_P(Layers, TiledRealData, ::testing::Values(
    TiledCase{"BgtPartitionTinyTiles10cm", bgt, "bgt_maaiveld_partition", 0.1, 20, 0, true, 0, 14},
    TiledCase{"BgtPartitionSmallTiles1m", bgt, "bgt_maaiveld_partition", 1.0, 150, 0, true, 0, 50},
    TiledCase{"BgtPartitionCascadeTest1m", bgt, "bgt_maaiveld_partition", 1.0, 150, 0, true, 1, 50},
    TiledCase{"BgtPartitionBalanced1cm", bgt, "bgt_maaiveld_partition", 0.01, 0, 2000, true, 0, 9},
    TiledCase{"AndorraSmallTiles", "snapoly_andorra/andorra.gpkg", "andorra", 1e-6, 0.01, 100000, false, 0, 1},
    // 5 m at Monaco's mean latitude (as --tolerance-m 5 gives it) in the default budget's two
    // tiles (16 smaller ones did not show it): a merge put the moved vertex's edges back in the
    // order of a walk round it, which starts at whatever face CGAL keeps for the vertex (another
    // in a tile); the crossings they made were numbered in that order and a centroid later summed
    // them in id order: one vertex one ulp off the untiled run (fixed in Mesh::replace). Buildings
    // 880 and 4005 lose their shared boundary here (a 10 m chain of vertices closer than t merges
    // into one point): reported (210, decided by the stitch from both tiles' evidence, by the
    // engine untiled), pinned below; unreported until 210 came in.
    TiledCase{"MonacoMultipolygons5m", "osm_monaco_osrm_2020/monaco_osrm_2020.gpkg", "multipolygons",
              6.217106820017268e-05, 0, 100000, false, 0, 640, 1}), case_name);

INSTANTIATE_TEST_SUITE_P(Layers, TiledRealDataSlow, ::testing::Values(
    TiledCase{"MonacoMultipolygons1e5", "osm_monaco_osrm_2020/monaco_osrm_2020.gpkg", "multipolygons", 1e-5, 0.003, 100000, false, 0, 144},
    // A grid: the balanced plan makes NJ shore one tile (its sea edges would put most of the
    // layer in one tile's box, BucketMaker::run), and this case is about cutting it.
    TiledCase{"NjshoreOnePolygon254kVertices", "osm_hard_polygons_planetiler/planetiler_hard_polygons.gpkg", "njshore", 1e-6, 0.6, 20000, false, 0, 1},
    TiledCase{"NaturalEarthOcean6823Holes", "natural_earth/natural_earth.gpkg", "ne_10m_ocean", 1e-5, 0, 50000, false, 0, 1},
    TiledCase{"NaturalEarthLand", "natural_earth/natural_earth.gpkg", "ne_10m_land", 1e-5, 0, 50000, false, 0, 0},
    TiledCase{"JakartaBuildings", "osm_buildings_mvt_boston_jakarta/jakarta_buildings_z13.gpkg", "building", 1e-6, 0, 20000, false, 0, 0}), case_name);

} // namespace
} // namespace trisnap
