// assess on hand-made layers with one defect each and a known answer.
#include "assess_fixture.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace trisnap::test {
namespace {

constexpr double k_eps = 1e-12;

TEST(AssessDefects, IdenticalCoverageIsClean)
{
    const std::vector<Item> grid{{1, square(0, 0, 1)}, {2, square(1, 0, 1)}, {3, square(0, 1, 1)}, {4, square(1, 1, 1)}};
    const AssessReport r = assess_items(grid, grid, 0.1);
    EXPECT_EQ(r.n_in, 4);
    EXPECT_EQ(r.n_matched, 4);
    EXPECT_EQ(r.n_missing + r.n_extra + r.n_attr_mismatch + r.n_invalid + r.n_empty, 0);
    EXPECT_EQ(r.n_overlaps + r.gaps_new + r.n_crossings, 0);
    EXPECT_EQ(r.n_shared_in, 4); // the four side-sharing pairs; corner touches share no length
    EXPECT_DOUBLE_EQ(*r.min_vertex_vertex, 1.0);
    EXPECT_DOUBLE_EQ(*r.min_vertex_edge, 1.0);
    EXPECT_EQ(r.max_hausdorff, 0.0);
    EXPECT_EQ(r.area_change, 0.0);
    EXPECT_TRUE(r.contract_holds());
}

TEST(AssessDefects, BowtieIsInvalidAndCrossesItself)
{
    const AssessReport r = assess_items({{1, square(0, 0, 2)}}, {{1, "POLYGON((0 0,2 2,2 0,0 2,0 0))"}}, 0.1);
    EXPECT_EQ(r.n_invalid, 1);
    ASSERT_EQ(r.invalid.size(), 1u);
    EXPECT_EQ(r.invalid[0].fid_a, 1);
    EXPECT_NE(r.invalid[0].text.find("Self-intersection"), std::string::npos) << r.invalid[0].text;
    EXPECT_NEAR(r.invalid[0].x, 1, k_eps);
    EXPECT_NEAR(r.invalid[0].y, 1, k_eps);
    EXPECT_EQ(r.n_crossings, 1);
    ASSERT_EQ(r.crossings.size(), 1u);
    EXPECT_NEAR(r.crossings[0].x, 1, k_eps);
    EXPECT_FALSE(r.contract_holds());
}

TEST(AssessDefects, OverlapOfKnownArea)
{
    const std::vector<Item> in{{1, square(0, 0, 2)}, {2, square(3, 0, 2)}};
    const std::vector<Item> out{{1, square(0, 0, 2)}, {2, "POLYGON((1 0,3 0,3 2,1 2,1 0))"}};
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_NEAR(r.overlap_area, 2.0, k_eps);
    ASSERT_EQ(r.overlaps.size(), 1u);
    EXPECT_EQ(r.overlaps[0].fid_a, 1);
    EXPECT_EQ(r.overlaps[0].fid_b, 2);
    EXPECT_NEAR(r.overlaps[0].x, 1.5, k_eps);
    EXPECT_NEAR(r.overlaps[0].y, 1.0, k_eps);
    EXPECT_EQ(r.n_overlaps_new, 1);
    EXPECT_TRUE(r.overlaps[0].is_new);
}

// Two Jakarta buildings (FIDs 46507 and 46510 of jakarta_buildings_z13) where a vertex of one
// lies within an ulp of the other's edge: GEOS's intersection of the pair gave 6.9e-18 m2 in one
// operand order and 0 in the other, and the layer judged against itself had a "new" overlap (the
// output's pair and the input's pair were passed in opposite orders). Whatever order the features
// come in, a layer against itself has no new overlap, and the pair's verdict is the same.
TEST(AssessDefects, ALayerAgainstItselfHasNoNewOverlap)
{
    const std::string a = "POLYGON((11895733.477665441 -708079.1888339975,11895739.449308274 -708067.2455483279,"
                          "11895747.809608243 -708072.0228625957,11895741.837965408 -708082.7718196983,"
                          "11895733.477665441 -708079.1888339975))";
    const std::string b = "POLYGON((11895732.283336874 -708067.2455483279,11895737.060651142 -708054.1079340914,"
                          "11895743.032293975 -708055.3022626583,11895738.25497971 -708069.6342054618,"
                          "11895732.283336874 -708067.2455483279))";
    std::vector<std::int64_t> overlaps;
    for (const std::vector<Item>& items : {std::vector<Item>{{46507, a}, {46510, b}}, std::vector<Item>{{46510, b}, {46507, a}},
                                           std::vector<Item>{{2, b}, {1, a}}, std::vector<Item>{{1, a}, {2, b}}}) {
        const AssessReport r = assess_items(items, items, 0.01);
        EXPECT_EQ(r.n_overlaps_new, 0) << items[0].fid << ", " << items[1].fid;
        EXPECT_EQ(r.n_invalid, 0);
        overlaps.push_back(r.n_overlaps);
    }
    EXPECT_EQ(overlaps[0], overlaps[1]) << "the same pair, listed in the other order";
    EXPECT_EQ(overlaps[2], overlaps[3]) << "the same, with other FIDs";
}

TEST(AssessDefects, NestedPolygonWithoutBoundaryContactOverlaps)
{
    const std::vector<Item> out{{1, square(0, 0, 10)}, {2, square(2, 2, 3)}};
    const AssessReport r = assess_items(out, out, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_EQ(r.n_overlaps_new, 0); // the input overlapped the same way
    EXPECT_NEAR(r.overlap_area, 9.0, k_eps);
    EXPECT_EQ(r.n_crossings, 0);
    // A polygon inside another's hole does not overlap it.
    const std::vector<Item> holed{{1, "POLYGON((0 0,10 0,10 10,0 10,0 0),(1 1,9 1,9 9,1 9,1 1))"}, {2, square(2, 2, 3)}};
    EXPECT_EQ(assess_items(holed, holed, 0.1).n_overlaps, 0);
}

TEST(AssessDefects, OverlapsThroughSharedEdgesAndVertices)
{
    // Boundaries meeting only at common vertices and identical edges: decided without GEOS.
    const std::vector<Item> triangle{{1, square(0, 0, 2)}, {2, "POLYGON((0 0,2 0,2 2,0 0))"}};
    AssessReport r = assess_items(triangle, triangle, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_NEAR(r.overlap_area, 2.0, k_eps);
    EXPECT_EQ(r.n_crossings, 0);
    const std::vector<Item> twice{{1, square(0, 0, 2)}, {2, "POLYGON((0 0,0 2,2 2,2 0,0 0))"}}; // other orientation
    r = assess_items(twice, twice, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_NEAR(r.overlap_area, 4.0, k_eps);
    // A polygon filling another's hole exactly shares every hole edge, on the other side.
    const std::vector<Item> filled{{1, "POLYGON((0 0,4 0,4 4,0 4,0 0),(1 1,1 3,3 3,3 1,1 1))"}, {2, square(1, 1, 2)}};
    EXPECT_EQ(assess_items(filled, filled, 0.1).n_overlaps, 0);
    // Diagonal through a shared corner: the triangle's edge inside the square decides.
    const std::vector<Item> inside{{1, square(0, 0, 2)}, {2, "POLYGON((0 0,2 2,3 0,0 0))"}};
    r = assess_items(inside, inside, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_NEAR(r.overlap_area, 2.0, k_eps);
}

TEST(AssessDefects, LostSharedBoundaryIsANewGap)
{
    const std::vector<Item> in{{1, square(0, 0, 1)}, {2, square(1, 0, 1)}};
    const std::vector<Item> out{{1, square(0, 0, 1)}, {2, square(1.5, 0, 1)}};
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_shared_in, 1);
    EXPECT_EQ(r.gaps_new, 1);
    ASSERT_EQ(r.gaps_new_examples.size(), 1u);
    EXPECT_EQ(r.gaps_new_examples[0].fid_a, 1);
    EXPECT_EQ(r.gaps_new_examples[0].fid_b, 2);
    EXPECT_NEAR(r.gaps_new_examples[0].value, 1.0, k_eps);
    EXPECT_NEAR(r.gaps_new_examples[0].x, 1.0, k_eps);
    EXPECT_NEAR(r.gaps_new_examples[0].y, 0.5, k_eps);
}

TEST(AssessDefects, SharedBoundaryOfAtMostTwoTDoesNotCount)
{
    // The pair shares x = 1 for y in [0.85, 1]: 0.15 <= 2T.
    const std::vector<Item> in{{1, square(0, 0, 1)}, {2, "POLYGON((1 0.85,2 0.85,2 2,1 2,1 0.85))"}};
    const std::vector<Item> out{{1, square(0, 0, 1)}, {2, "POLYGON((1.5 0.85,2 0.85,2 2,1.5 2,1.5 0.85))"}};
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_shared_in, 0);
    EXPECT_EQ(r.gaps_new, 0);
}

TEST(AssessDefects, CrossingsAndTouches)
{
    const auto crossings = [](const std::vector<Item>& out) { return assess_items(out, out, 0.01); };
    AssessReport r = crossings({{1, "LINESTRING(0 0,2 2)"}, {2, "LINESTRING(0 2,2 0)"}});
    EXPECT_EQ(r.n_crossings, 1);
    ASSERT_EQ(r.crossings.size(), 1u);
    EXPECT_EQ(r.crossings[0].fid_a, 1);
    EXPECT_EQ(r.crossings[0].fid_b, 2);
    EXPECT_NEAR(r.crossings[0].x, 1, k_eps);
    EXPECT_NEAR(r.crossings[0].y, 1, k_eps);
    // An endpoint on the other's interior (a T) crosses; it lies exactly there.
    r = crossings({{1, "LINESTRING(0 0,2 0)"}, {2, "LINESTRING(1 0,1 1)"}});
    EXPECT_EQ(r.n_crossings, 1);
    EXPECT_EQ(r.crossings.at(0).x, 1.0);
    EXPECT_EQ(*r.min_vertex_edge, 0.0);
    // A shared endpoint does not; nor does a shared identical segment.
    EXPECT_EQ(crossings({{1, "LINESTRING(0 0,1 0)"}, {2, "LINESTRING(1 0,2 1)"}}).n_crossings, 0);
    EXPECT_EQ(crossings({{1, "LINESTRING(0 0,1 0)"}, {2, "LINESTRING(0 0,1 0,2 1)"}}).n_crossings, 0);
    // A collinear partial overlap does; so does a self-crossing within one feature.
    EXPECT_EQ(crossings({{1, "LINESTRING(0 0,2 0)"}, {2, "LINESTRING(1 0,3 0)"}}).n_crossings, 1);
    r = crossings({{7, "LINESTRING(0 0,2 2,2 0,0 2)"}});
    EXPECT_EQ(r.n_crossings, 1);
    EXPECT_EQ(r.crossings.at(0).fid_a, 7);
    EXPECT_EQ(r.crossings.at(0).fid_b, 7);
}

TEST(AssessDefects, VertexAtKnownDistanceFromAnEdge)
{
    const std::vector<Item> out{{1, "LINESTRING(0 0,10 0)"}, {2, "LINESTRING(5 0.3,5 5)"}};
    const AssessReport r = assess_items(out, out, 1.0);
    EXPECT_NEAR(*r.min_vertex_edge, 0.3, k_eps);
    const AssessExample& e = r.closest_vertex_edge.at(0);
    EXPECT_EQ(e.fid_a, 2); // the vertex
    EXPECT_EQ(e.fid_b, 1); // the edge
    EXPECT_EQ(e.x, 5.0);
    EXPECT_EQ(e.y, 0.3);
    EXPECT_NEAR(e.x2, 5.0, k_eps);
    EXPECT_NEAR(e.y2, 0.0, k_eps);
    EXPECT_EQ(e.edge[2], 10.0);
    EXPECT_FALSE(r.contract_holds()); // 0.3 < T/2
    EXPECT_EQ(r.n_crossings, 0);
}

TEST(AssessDefects, TwoVerticesAtKnownDistance)
{
    const std::vector<Item> out{{1, "LINESTRING(-5 0,0 0)"}, {2, "LINESTRING(0.25 0,0.25 -7)"}};
    const AssessReport r = assess_items(out, out, 1.0);
    EXPECT_NEAR(*r.min_vertex_vertex, 0.25, k_eps);
    const AssessExample& e = r.closest_vertex_vertex.at(0);
    EXPECT_EQ(std::min(e.x, e.x2), 0.0);
    EXPECT_EQ(std::max(e.x, e.x2), 0.25);
    // The same coordinates twice are one vertex, not a distance of 0.
    const std::vector<Item> joined{{1, "LINESTRING(-5 0,0 0)"}, {2, "LINESTRING(0 0,0 -7)"}};
    EXPECT_NEAR(*assess_items(joined, joined, 1.0).min_vertex_vertex, 5.0, k_eps);
}

TEST(AssessDefects, MissingExtraEmptyAndAttributeMismatch)
{
    const std::vector<Item> in{{1, square(0, 0, 1), "a"}, {2, square(2, 0, 1), "b"}, {3, square(4, 0, 1), "c"},
                               {5, square(6, 0, 1), "e"}};
    const std::vector<Item> out{{1, square(0, 0, 1), "a"}, {3, square(4, 0, 1), "X"}, {4, square(8, 0, 1), "d"},
                                {5, "", "e"}};
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_missing, 2); // fid 2 absent, fid 5 empty
    ASSERT_EQ(r.missing.size(), 2u);
    EXPECT_EQ(r.missing[0].fid_a, 2);
    EXPECT_EQ(r.missing[1].fid_a, 5);
    EXPECT_EQ(r.n_extra, 1);
    EXPECT_EQ(r.extra.at(0).fid_b, 4);
    EXPECT_EQ(r.n_empty, 1);
    EXPECT_EQ(r.n_attr_mismatch, 1);
    EXPECT_EQ(r.attr_mismatch.at(0).fid_a, 3);
    EXPECT_EQ(r.attr_mismatch.at(0).text, "name: 'c' vs 'X'");
}

TEST(AssessDefects, MatchingByKeyField)
{
    const std::vector<Item> in{{1, square(0, 0, 1), "a"}, {2, square(2, 0, 1), "b"}};
    const std::vector<Item> out{{10, square(2, 0, 1), "b"}, {11, square(0, 0, 1), "a"}};
    const AssessReport by_key = assess_items(in, out, 0.1, "name");
    EXPECT_EQ(by_key.n_matched, 2);
    EXPECT_EQ(by_key.n_missing + by_key.n_extra, 0);
    EXPECT_EQ(by_key.max_hausdorff, 0.0);
    const AssessReport by_fid = assess_items(in, out, 0.1);
    EXPECT_EQ(by_fid.n_missing, 2);
    EXPECT_EQ(by_fid.n_extra, 2);
    EXPECT_THROW(assess_items(in, out, 0.1, "nope"), std::invalid_argument);
    EXPECT_THROW(assess_items(in, out, 0.0), std::invalid_argument);
}

TEST(AssessDefects, KnownHausdorff)
{
    // A unit square moved by (0.3, 0.4): the farthest points are opposite corners, 0.5 away.
    AssessReport r = assess_items({{1, square(0, 0, 1)}}, {{1, square(0.3, 0.4, 1)}}, 0.01);
    EXPECT_NEAR(r.max_hausdorff, 0.5, 0.01 * 1e-3);
    EXPECT_LE(r.max_hausdorff, 0.5 + k_eps);
    // The farthest point is inside an edge, far from every vertex: (5, 0) is 1 from the output.
    r = assess_items({{1, "LINESTRING(0 0,10 0)"}}, {{1, "MULTILINESTRING((0 0,4 0),(6 0,10 0))"}}, 0.01);
    EXPECT_NEAR(r.max_hausdorff, 1.0, 0.01 * 1e-3);
    EXPECT_NEAR(r.largest_hausdorff.at(0).x, 5.0, 0.01);
    // A vertex moved off the line: 1 at the vertex.
    r = assess_items({{1, "LINESTRING(0 0,10 0)"}}, {{1, "LINESTRING(0 0,5 1,10 0)"}}, 0.01);
    EXPECT_NEAR(r.max_hausdorff, 1.0, k_eps);
    EXPECT_NEAR(r.p99_hausdorff, 1.0, k_eps);
}

TEST(AssessDefects, AreaChange)
{
    const AssessReport r = assess_items({{1, square(0, 0, 1)}, {2, "LINESTRING(5 5,6 6)"}},
                                        {{1, "POLYGON((0 0,2 0,2 1,0 1,0 0))"}, {2, "LINESTRING(5 5,6 6)"}}, 0.1);
    EXPECT_NEAR(r.area_in, 1.0, k_eps);
    EXPECT_NEAR(r.area_change, 1.0, k_eps);
    const AssessReport holed = assess_items({{1, square(0, 0, 4)}}, {{1, "POLYGON((0 0,4 0,4 4,0 4,0 0),(1 1,2 1,2 2,1 2,1 1))"}}, 0.1);
    EXPECT_NEAR(holed.area_change, -1.0 / 16, k_eps);
}

TEST(AssessDefects, JsonHasTheStableKeys)
{
    const AssessReport r = assess_items({{1, square(0, 0, 1)}}, {{1, "POLYGON((0 0,2 2,2 0,0 2,0 0))"}}, 0.1);
    const nlohmann::json j = nlohmann::json::parse(assess_report_json(r));
    for (const char* key : {"n_in", "n_out", "n_missing", "n_extra", "n_attr_mismatch", "n_invalid", "n_empty",
                            "n_overlaps", "overlap_area", "gaps_new", "n_crossings", "min_vertex_vertex",
                            "min_vertex_edge", "max_hausdorff", "p99_hausdorff", "area_change", "tolerance",
                            "min_vertex_vertex_over_t", "min_vertex_edge_over_t", "max_hausdorff_over_t",
                            "contract_holds"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["n_invalid"], 1);
    EXPECT_EQ(j["contract_holds"], false);
    EXPECT_EQ(j["examples"]["invalid"][0]["fid"], 1);
    for (const char* list : {"invalid", "overlaps", "gaps_new", "crossings", "closest_vertex_edge",
                             "closest_vertex_vertex", "largest_hausdorff", "missing", "extra", "attr_mismatch"})
        EXPECT_TRUE(j["examples"].contains(list)) << list;
}

} // namespace
} // namespace trisnap::test
