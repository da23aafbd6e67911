// Problem 210 (shared_boundary_lost): two polygons that shared a boundary of at least t and share
// none after snapping, both still written, are reported on both, naming each other, untiled by
// the engine and tiled by the stitch from the tiles' evidence, with the same problems.
// The pair is the one trisnap assess found on Monaco at 5 m (buildings 880 and 4005, OSM ways
// 62661527 and 62665141): six vertices 2-3 m apart zigzag along their 9.7 m wall and merge
// into one point.
#include "tiled_check.hpp"

#include "core/shared_boundaries.hpp"
#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace trisnap {
namespace {

constexpr double k_five_m = 6.217106820017268e-05; // 5 m at Monaco's latitude, in degrees

Feature from_wkt(std::int64_t id, const char* wkt)
{
    Feature f;
    f.id = id;
    f.geometry = read_wkt(wkt);
    return f;
}

std::vector<Feature> monaco_pair()
{
    return {from_wkt(880, "POLYGON((7.366816 43.731894,7.366832 43.731908,7.366805 43.731925,7.366828 43.731943,"
                          "7.366807 43.731957,7.366832 43.73198,7.366789 43.732006,7.366725 43.731949,7.366816 43.731894))"),
            from_wkt(4005, "POLYGON((7.366995 43.731922,7.366981 43.731932,7.367001 43.731948,7.367031 43.731974,"
                           "7.366995 43.731995,7.366981 43.731983,7.366894 43.732036,7.366832 43.73198,7.366807 43.731957,"
                           "7.366828 43.731943,7.366805 43.731925,7.366832 43.731908,7.366816 43.731894,7.366902 43.731841,"
                           "7.366995 43.731922))")};
}

std::vector<const Problem*> with_code(const SnapResult& r, ProblemCode code)
{
    std::vector<const Problem*> out;
    for (const Problem& p : r.problems) {
        if (p.code == code) {
            out.push_back(&p);
        }
    }
    return out;
}

TEST(SharedBoundaryLost, AChainOfCloseVerticesThatMergesToAPointIsReported)
{
    const std::vector<Feature> in = monaco_pair();
    const CheckedRun run = snap_and_check(in, options_at(k_five_m), 0);
    ASSERT_FALSE(run.result.features[0].geometry.empty());
    ASSERT_FALSE(run.result.features[1].geometry.empty());
    const std::vector<const Problem*> lost = with_code(run.result, ProblemCode::shared_boundary_lost);
    // On the later feature of the pair in input order, naming the earlier, at the smallest point
    // (x, then y) of their wall.
    ASSERT_EQ(lost.size(), 1u) << run.report.summary();
    EXPECT_EQ(lost[0]->feature_id, 4005);
    EXPECT_NE(lost[0]->message.find("FID 880"), std::string::npos) << lost[0]->message;
    EXPECT_EQ(lost[0]->x, 7.366805);
    EXPECT_EQ(lost[0]->y, 43.731925);
    // The input order decides which one carries it.
    const SnapResult swapped = snap(std::vector<Feature>{in[1], in[0]}, options_at(k_five_m));
    const std::vector<const Problem*> other = with_code(swapped, ProblemCode::shared_boundary_lost);
    ASSERT_EQ(other.size(), 1u);
    EXPECT_EQ(other[0]->feature_id, 880);
    EXPECT_NE(other[0]->message.find("FID 4005"), std::string::npos) << other[0]->message;
    // The independent checker sees the loss, and sees it reported.
    EXPECT_EQ(run.report.n_shared_lost, 0u) << run.report.summary();
    EXPECT_EQ(run.report.n_shared_lost_reported, 1u) << run.report.summary();
}

TEST(SharedBoundaryLost, NothingIsReportedWhereTheWallSurvives)
{
    const CheckedRun run = snap_and_check(monaco_pair(), options_at(k_five_m / 5), 0);
    EXPECT_TRUE(with_code(run.result, ProblemCode::shared_boundary_lost).empty());
    EXPECT_EQ(run.report.n_shared_lost + run.report.n_shared_lost_reported, 0u) << run.report.summary();
    EXPECT_TRUE(contract_holds(run.report, k_five_m / 5)) << run.report.summary();
}

// Seams through the wall (grid tiles of 5e-5 degrees: y = 43.7319 and 43.73195 cut it): each
// tile sees part of it, the stitch merges their evidence and reports what the untiled run does.
TEST(SharedBoundaryLost, TilesCuttingTheWallReportWhatTheUntiledRunReports)
{
    const std::vector<Feature> in = monaco_pair();
    const SnapOptions o = options_at(k_five_m);
    const SnapResult untiled = snap(in, o);
    for (const double size : {5e-5, 2e-5}) {
        const TiledRun run = tiled_and_check(in, o, tiles_of(size), 0);
        EXPECT_GT(run.tiled.stitch.leaves, 2u) << "the seams should cut the wall";
        EXPECT_EQ(problems_without_seams(untiled.problems), problems_without_seams(run.tiled.result.problems));
        const std::vector<const Problem*> lost = with_code(run.tiled.result, ProblemCode::shared_boundary_lost);
        const std::vector<const Problem*> alone = with_code(untiled, ProblemCode::shared_boundary_lost);
        ASSERT_EQ(lost.size(), 1u);
        ASSERT_EQ(alone.size(), 1u);
        EXPECT_EQ(lost[0]->message, alone[0]->message); // the same words, the same place
        EXPECT_EQ(lost[0]->x, alone[0]->x);
        EXPECT_EQ(lost[0]->y, alone[0]->y);
        EXPECT_TRUE(differing(untiled, run.tiled.result).empty());
        EXPECT_EQ(run.report.n_shared_lost, 0u) << run.report.summary();
        EXPECT_EQ(run.report.n_shared_lost_reported, 1u) << run.report.summary();
    }
}

Path rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}; }

Feature polygon(std::int64_t id, Path ring)
{
    Feature f;
    f.id = id;
    f.geometry.type = Geometry::Type::Polygon;
    f.geometry.polygons = {Polygon{{std::move(ring)}}};
    return f;
}

// A neighbour that vanished (201) says more than a lost boundary would: its survivor gets no
// 210, whichever comes first in the input, tiled or not.
TEST(SharedBoundaryLost, ANeighbourThatCollapsedIsNotALostBoundary)
{
    const double t = 1.0;
    const Feature big = polygon(1, rect(0, 0, 10, 10));
    const Feature thin = polygon(2, rect(10, 2, 10.1, 8));
    for (const std::vector<Feature>& in : {std::vector<Feature>{big, thin}, std::vector<Feature>{thin, big}}) {
        const SnapResult r = snap(in, options_at(t));
        EXPECT_EQ(with_code(r, ProblemCode::collapsed_polygon).size(), 1u);
        EXPECT_TRUE(with_code(r, ProblemCode::shared_boundary_lost).empty());
        const TiledRun tiled = tiled_and_check(in, options_at(t), tiles_of(3), 1);
        EXPECT_GT(tiled.tiled.stitch.leaves, 1u) << "the case should cut the layer";
        EXPECT_EQ(problems_without_seams(r.problems), problems_without_seams(tiled.tiled.result.problems));
        // the evidence a tile gives: the pair lost its boundary (only the collapse excuses it)
        SnapOptions bounded = options_at(t);
        bounded.report_region = Region{-100, -100, 100, 100};
        const SnapResult e = snap(in, bounded);
        ASSERT_EQ(e.features[0].shared.size(), 1u);
        EXPECT_TRUE(detail::lost_candidate(e.features[0].shared[0], t));
    }
}

// A shared piece shorter than t has ends closer than t: snapping must merge them, so its loss is
// no defect and not reported. The evidence (what a tile would give the stitch: a bounded report
// region) shows the loss and the length that excuses it; 1.5 t of shared boundary survives.
TEST(SharedBoundaryLost, ABoundaryShorterThanTheToleranceMayCollapse)
{
    const double t = 1.0;
    for (const double shared : {0.8, 1.5}) {
        const std::vector<Feature> in{polygon(1, rect(0, 0, 10, 10)), polygon(2, rect(10, 10 - shared, 20, 20))};
        const SnapResult r = snap(in, options_at(t));
        ASSERT_FALSE(r.features[0].geometry.empty());
        ASSERT_FALSE(r.features[1].geometry.empty());
        EXPECT_TRUE(with_code(r, ProblemCode::shared_boundary_lost).empty()) << "shared " << shared;
        SnapOptions bounded = options_at(t);
        bounded.report_region = Region{-100, -100, 100, 100};
        const SnapResult e = snap(in, bounded);
        ASSERT_EQ(e.features[0].shared.size(), 1u);
        const SharedBoundary& s = e.features[0].shared[0];
        EXPECT_EQ(s.other, 2);
        EXPECT_EQ(s.other_position, 1u);
        EXPECT_TRUE(s.before);
        EXPECT_EQ(s.after, shared > t) << "shared " << shared;
        EXPECT_NEAR(s.length, shared, 1e-12);
        EXPECT_EQ(s.x, 10.0);
        EXPECT_EQ(s.y, 10 - shared);
        EXPECT_TRUE(with_code(e, ProblemCode::shared_boundary_lost).empty()) << "a tile's run leaves 210 to the stitch";
    }
}

// Stacked copies of one polygon would make the pairs quadratic in the copies: an edge bounding
// more than k_max_stacked polygons gives no evidence. 2,000 copies and a neighbour: no pair
// recorded on their edges (4 * 10^6 pairs otherwise), while a pair of 8 still is.
TEST(SharedBoundaryLost, StackedCopiesGiveNoQuadraticEvidence)
{
    const double t = 0.1;
    SnapOptions bounded = options_at(t);
    bounded.report_region = Region{-100, -100, 100, 100};
    for (const std::size_t copies : {std::size_t{2000}, detail::k_max_stacked - 1}) {
        std::vector<Feature> in;
        for (std::size_t k = 0; k < copies; ++k) {
            in.push_back(polygon(static_cast<std::int64_t>(k), rect(0, 0, 10, 10)));
        }
        in.push_back(polygon(-1, rect(10, 0, 20, 10)));
        const SnapResult r = snap(in, bounded);
        std::size_t records = 0;
        for (const FeatureOutput& f : r.features) {
            records += f.shared.size();
        }
        EXPECT_EQ(records, copies > detail::k_max_stacked ? 0u : (copies + 1) * copies) << copies << " copies";
        EXPECT_TRUE(with_code(snap(in, options_at(t)), ProblemCode::shared_boundary_lost).empty());
    }
}

} // namespace
} // namespace trisnap
