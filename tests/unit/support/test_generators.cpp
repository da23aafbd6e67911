// The generators are deterministic and produce what they promise, checked with GEOS directly.
#include "contract_checker.hpp"
#include "core/wkt.hpp"
#include "generators.hpp"

#include <geos_c.h>
#include <gtest/gtest.h>

#include <memory>

namespace trisnap {
namespace {

/// Sum of areas, union area and invalid count of a layer, straight from GEOS.
struct Areas {
    double sum = 0.0;
    double union_area = 0.0;
    int invalid = 0;
};

Areas geos_areas(const std::vector<Feature>& features) {
    GEOSContextHandle_t h = GEOS_init_r();
    GEOSWKTReader* reader = GEOSWKTReader_create_r(h);
    std::vector<GEOSGeometry*> geoms;
    Areas a;
    for (const Feature& f : features) {
        GEOSGeometry* g = GEOSWKTReader_read_r(h, reader, to_wkt(f.geometry).c_str());
        double area = 0.0;
        GEOSArea_r(h, g, &area);
        a.sum += area;
        a.invalid += GEOSisValid_r(h, g) == 1 ? 0 : 1;
        geoms.push_back(g);
    }
    GEOSGeometry* all = GEOSGeom_createCollection_r(h, GEOS_GEOMETRYCOLLECTION, geoms.data(),
                                                    static_cast<unsigned>(geoms.size()));
    GEOSGeometry* u = GEOSUnaryUnion_r(h, all);
    GEOSArea_r(h, u, &a.union_area);
    GEOSGeom_destroy_r(h, u);
    GEOSGeom_destroy_r(h, all);
    GEOSWKTReader_destroy_r(h, reader);
    GEOS_finish_r(h);
    return a;
}

std::vector<std::string> wkts(const std::vector<Feature>& features) {
    std::vector<std::string> out;
    for (const Feature& f : features)
        out.push_back(std::to_string(f.id) + ";" + to_wkt(f.geometry));
    return out;
}

std::vector<CheckedFeature> checked(const std::vector<Feature>& features) {
    std::vector<CheckedFeature> out;
    for (const Feature& f : features)
        out.push_back({f.id, to_wkt(f.geometry)});
    return out;
}

TEST(Generators, UniformMappingIsStable) {
    std::mt19937_64 rng(42);
    const double first = uniform(rng, 0.0, 1.0);
    std::mt19937_64 again(42);
    EXPECT_EQ(uniform(again, 0.0, 1.0), first);
    // mt19937_64's 10000th output is fixed by the standard: the mapping on top is ours.
    std::mt19937_64 reference;
    reference.discard(9999);
    EXPECT_EQ(reference(), 9981545732273789042ull);
    for (int i = 0; i < 1000; ++i) {
        const std::int64_t k = uniform_int(rng, -3, 3);
        EXPECT_GE(k, -3);
        EXPECT_LE(k, 3);
    }
}

TEST(Generators, SameSeedSameLayerOtherSeedOtherLayer) {
    EXPECT_EQ(wkts(perturbed_grid_coverage(4, 3, 10.0, 0.2, 7, 3)),
              wkts(perturbed_grid_coverage(4, 3, 10.0, 0.2, 7, 3)));
    EXPECT_NE(wkts(perturbed_grid_coverage(4, 3, 10.0, 0.2, 7, 3)),
              wkts(perturbed_grid_coverage(4, 3, 10.0, 0.2, 8, 3)));
    EXPECT_EQ(wkts(near_degenerate_polygons(50, 100.0, 1.0, 3)),
              wkts(near_degenerate_polygons(50, 100.0, 1.0, 3)));
    EXPECT_NE(wkts(near_degenerate_polygons(50, 100.0, 1.0, 3)),
              wkts(near_degenerate_polygons(50, 100.0, 1.0, 4)));
    EXPECT_EQ(wkts(vertex_cluster(7, 1.0, 5)), wkts(vertex_cluster(7, 1.0, 5)));
}

TEST(Generators, CoverageIsAValidPartitionOfTheRectangle) {
    for (int points : {0, 5}) {
        const auto cells = perturbed_grid_coverage(12, 9, 10.0, 0.24, 11, points, 0.004);
        ASSERT_EQ(cells.size(), 108u);
        EXPECT_EQ(vertex_count(cells), 108u * (5u + 4u * static_cast<unsigned>(points)));
        const Areas a = geos_areas(cells);
        EXPECT_EQ(a.invalid, 0);
        EXPECT_NEAR(a.sum, 120.0 * 90.0, 1e-9 * 120.0 * 90.0);
        EXPECT_NEAR(a.union_area, 120.0 * 90.0, 1e-9 * 120.0 * 90.0); // no overlaps, no gaps
    }
}

TEST(Generators, CoverageSharesEdgesExactly) {
    const auto cells = checked(perturbed_grid_coverage(6, 5, 10.0, 0.2, 3, 4));
    // Extra edge points fall anywhere along an edge, so only a tiny t is met by the input.
    const double t = 1e-7;
    const ContractReport r = check_contract(cells, cells, t);
    EXPECT_TRUE(contract_holds(r, t)) << r.summary();
    // Any two neighbours moved apart by a hair would be caught as a lost shared boundary.
    std::vector<CheckedFeature> nudged = cells;
    Feature moved = perturbed_grid_coverage(6, 5, 10.0, 0.2, 3, 4)[7];
    for (Coord& c : moved.geometry.polygons[0].rings[0])
        c.x += 1e-6;
    nudged[7].wkt = to_wkt(moved.geometry);
    EXPECT_GE(check_contract(cells, nudged, t).n_shared_lost, 2u);
}

TEST(Generators, NearDegeneratePolygonsAreValidAndCloseToEachOther) {
    const double t = 0.5;
    const auto polygons = near_degenerate_polygons(300, 200.0, t, 17);
    ASSERT_EQ(polygons.size(), 300u);
    EXPECT_EQ(geos_areas(polygons).invalid, 0);
    const ContractReport r = check_contract(checked(polygons), checked(polygons), t);
    EXPECT_EQ(r.n_invalid, 0u);
    EXPECT_LT(r.min_vertex_vertex, 0.5 * t); // near-coincident vertices are there to be snapped
    EXPECT_LT(r.min_vertex_edge, 0.5 * t);
    EXPECT_GT(r.n_close_vertex_pairs, 50u);
}

TEST(Generators, VertexClusterTrianglesDoNotOverlap) {
    const double t = 2.0;
    const auto fan = vertex_cluster(9, t, 1);
    const Areas a = geos_areas(fan);
    EXPECT_EQ(a.invalid, 0);
    EXPECT_NEAR(a.sum, a.union_area, 1e-9 * a.sum);
    for (const Feature& f : fan) {
        const Coord apex = f.geometry.polygons[0].rings[0][0];
        EXPECT_LE(std::hypot(apex.x, apex.y), 0.5 * t);
    }
}

TEST(Generators, DenseLineAndSquare) {
    const Feature line = dense_line(3, 80, 0.4, 0.1, 9);
    ASSERT_EQ(line.geometry.lines[0].size(), 80u);
    EXPECT_DOUBLE_EQ(line.geometry.lines[0][79].x, 79 * 0.4);
    EXPECT_EQ(to_wkt(square(1, 0, 0, 2).geometry), "POLYGON ((0 0, 2 0, 2 2, 0 2, 0 0))");
}

} // namespace
} // namespace trisnap
