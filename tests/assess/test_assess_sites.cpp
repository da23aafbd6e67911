// Sites: the report's examples as places to look at (missing features, drift with its far and
// near point, close pairs with shared boundaries counted once), and the one definition of
// "worst" that assess and render share: breaches nobody explained first, kinds in turn, no
// feature twice, nothing where nothing changed.
#include "assess_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace trisnap::test {
namespace {

using assess::Site;
using assess::SiteKind;

std::vector<Site> of_kind(const std::vector<Site>& sites, SiteKind kind)
{
    std::vector<Site> out;
    std::copy_if(sites.begin(), sites.end(), std::back_inserter(out), [&](const Site& s) { return s.kind == kind; });
    return out;
}

std::vector<Site> breaches(const std::vector<Site>& sites, SiteKind kind)
{
    std::vector<Site> out = of_kind(sites, kind);
    std::erase_if(out, [](const Site& s) { return !s.breach; });
    return out;
}

std::string rect(double x0, double y0, double x1, double y1)
{
    return "POLYGON((" + std::to_string(x0) + " " + std::to_string(y0) + "," + std::to_string(x1) + " " + std::to_string(y0) +
           "," + std::to_string(x1) + " " + std::to_string(y1) + "," + std::to_string(x0) + " " + std::to_string(y1) + "," +
           std::to_string(x0) + " " + std::to_string(y0) + "))";
}

TEST(AssessSites, MissingIsAnInputFeatureWithoutOutput)
{
    const auto sites = report_sites(assess_items({{1, square(0, 0, 10)}, {2, rect(20, 0, 20.4, 0.2)}}, {{1, square(0, 0, 10)}}, 1.0));
    const auto missing = of_kind(sites, SiteKind::missing);
    ASSERT_EQ(missing.size(), 1u);
    EXPECT_EQ(missing[0].fid, 2);
    EXPECT_TRUE(missing[0].breach);
    EXPECT_DOUBLE_EQ(missing[0].at.x, 20.2) << "the centre of the lost feature";
    EXPECT_NEAR(missing[0].value, 2 * 0.08 / 1.2, 1e-12) << "mean width 2A/P";
    EXPECT_DOUBLE_EQ(missing[0].extent.xmax, 20.4);
    EXPECT_TRUE(of_kind(sites, SiteKind::drift).empty()) << "an unchanged feature has no drift";
}

TEST(AssessSites, DriftIsTheExactHausdorffWithItsFarAndNearPoint)
{
    const std::vector<Item> in{{1, square(0, 0, 10)}};
    auto drift = of_kind(report_sites(assess_items(in, {{1, "POLYGON((0 0,10 0,13 10,0 10,0 0))"}}, 1.0)), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_NEAR(drift[0].value, 3.0, 1e-3);
    EXPECT_EQ(drift[0].at, (assess::Pt{13, 10})) << "the farthest point";
    EXPECT_EQ(drift[0].other, (assess::Pt{10, 10})) << "its nearest point on the other side";
    EXPECT_TRUE(drift[0].breach) << "3 > 2T";

    drift = of_kind(report_sites(assess_items(in, {{1, "POLYGON((0 0,10 0,11.5 10,0 10,0 0))"}}, 1.0)), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_NEAR(drift[0].value, 1.5, 1e-3);
    EXPECT_FALSE(drift[0].breach);
}

TEST(AssessSites, DriftSeesTheMiddleOfAnEdgeNotOnlyVertices)
{
    // The input's top edge bows out by 2.5 between two vertices 10 apart: no input vertex is
    // more than 0 from the output, yet the middle of the output's straight edge is 2.5 away
    // from the input (render measured vertices only and said 0 here).
    const std::vector<Item> in{{1, "POLYGON((0 0,10 0,10 10,5 12.5,0 10,0 0))"}};
    const std::vector<Item> out{{1, "POLYGON((0 0,10 0,10 10,0 10,0 0))"}};
    const auto drift = of_kind(report_sites(assess_items(in, out, 1.0)), SiteKind::drift);
    ASSERT_EQ(drift.size(), 1u);
    EXPECT_NEAR(drift[0].value, 2.5, 1e-3);
    EXPECT_TRUE(drift[0].breach);
}

TEST(AssessSites, ClosePairsCountSharedBoundariesOnce)
{
    // Two squares sharing an edge (not a defect) and a third 0.4 to the right of the second.
    const std::vector<Item> out{{1, square(0, 0, 10)}, {2, square(10, 0, 10)}, {3, rect(20.4, 0, 30, 10)}};
    const AssessReport r = assess_items(out, out, 1.0);
    const auto sites = report_sites(r);
    const auto vv = breaches(sites, SiteKind::vertex_vertex);
    ASSERT_EQ(vv.size(), 2u); // (20,0)-(20.4,0) and (20,10)-(20.4,10)
    for (const Site& s : vv) {
        EXPECT_NEAR(s.value, 0.4, 1e-12);
        EXPECT_EQ(s.at.x, 20.0);
        EXPECT_EQ(s.fid, 2);
        EXPECT_EQ(s.fid2, 3);
    }
    EXPECT_EQ(breaches(sites, SiteKind::vertex_edge).size(), 4u) << "each corner facing the gap, to the other side's edge";
    EXPECT_EQ(r.n_vv_breaches, 4) << "counted per vertex";
    EXPECT_EQ(r.n_ve_breaches, 4);
}

Site site(SiteKind kind, double x, double value, bool breach, std::int64_t fid)
{
    Site s;
    s.kind = kind;
    s.at = s.other = {x, 0};
    s.value = value;
    s.breach = breach;
    s.fid = fid;
    return s;
}

const auto k_always_changed = [](const Site&) { return true; };

TEST(AssessWorst, BreachesFirstAndEveryKindInTurn)
{
    std::vector<Site> sites{site(SiteKind::drift, 0, 5, true, 1),          site(SiteKind::drift, 100, 4, true, 2),
                            site(SiteKind::drift, 200, 1, false, 3),       site(SiteKind::vertex_edge, 300, 0.1, true, 4),
                            site(SiteKind::vertex_edge, 300.5, 0.2, true, 5), site(SiteKind::vertex_vertex, 400, 2, false, 6)};
    assess::sort_sites(sites);
    const auto worst = assess::pick_worst(sites, 4, 3.0, k_always_changed);
    ASSERT_EQ(worst.size(), 4u);
    EXPECT_EQ(worst[0].at.x, 0);   // drift breach
    EXPECT_EQ(worst[1].at.x, 300); // vertex-edge breach
    EXPECT_EQ(worst[2].at.x, 100); // second drift breach
    EXPECT_EQ(worst[3].at.x, 200); // then the rest, kinds in turn
    EXPECT_EQ(assess::pick_worst(sites, 10, 3.0, k_always_changed).size(), 5u) << "one site is a near duplicate";
}

TEST(AssessWorst, ExplainedBreachesComeAfterTheUnexplained)
{
    std::vector<Site> sites{site(SiteKind::drift, 0, 30, true, 1), site(SiteKind::drift, 100, 2.5, true, 2)};
    sites[0].excused_by = "209 thin_part_collapsed";
    assess::sort_sites(sites);
    const auto worst = assess::pick_worst(sites, 2, 3.0, k_always_changed);
    ASSERT_EQ(worst.size(), 2u);
    EXPECT_EQ(worst[0].fid, 2) << "2.5 T that nobody explained before 30 T the report explains";
    EXPECT_EQ(worst[1].fid, 1);
}

TEST(AssessWorst, NoFeatureTwiceAndNothingWhereNothingChanged)
{
    std::vector<Site> sites{site(SiteKind::drift, 0, 5, true, 1), site(SiteKind::vertex_edge, 100, 0.1, true, 7),
                            site(SiteKind::vertex_vertex, 200, 0.5, true, 8), site(SiteKind::drift, 300, 1, false, 9)};
    sites[1].fid2 = 1; // the vertex-edge pair involves feature 1 again
    sites[3].fid2 = 9;
    assess::sort_sites(sites);
    const auto unchanged = [](const Site& s) { return s.at.x != 300; };
    const auto worst = assess::pick_worst(sites, 10, 3.0, unchanged);
    ASSERT_EQ(worst.size(), 2u);
    EXPECT_EQ(worst[0].fid, 1);
    EXPECT_EQ(worst[1].fid, 8) << "the vertex-edge site shows feature 1 again; the last site shows no change";
}

TEST(AssessWorst, AssessListsTheSameWorstAsItsSitesGive)
{
    // The report's worst list is pick_worst over report_sites: render draws exactly these.
    const std::vector<Item> in{{1, square(0, 0, 10)}, {2, rect(20, 0, 30, 10)}, {3, rect(40, 0, 40.3, 0.3)}};
    const std::vector<Item> out{{1, square(0, 0, 10)}, {2, "POLYGON((20 0,30 0,33 10,20 10,20 0))"}};
    const AssessReport r = assess_items(in, out, 1.0);
    ASSERT_EQ(r.worst.size(), 2u);
    EXPECT_EQ(r.worst[0].kind, SiteKind::missing);
    EXPECT_EQ(r.worst[0].fid, 3);
    EXPECT_EQ(r.worst[1].kind, SiteKind::drift);
    EXPECT_EQ(r.worst[1].fid, 2);
    const std::vector<std::string> lines = worst_site_lines(r.worst, 1.0);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[1].rfind("#2 drift 3 T (> 2T), fid 2 at 33, 10", 0), 0u) << lines[1];
}

} // namespace
} // namespace trisnap::test
