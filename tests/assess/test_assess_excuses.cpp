// Honest verdicts: the contract is judged on defects that are new against the input, and a
// `trisnap snap --report` excuses exactly what its codes explain, per feature (or, for
// separations, at the reported place); everything else still fails.
#include "assess_fixture.hpp"

#include "assess/excuses.hpp"
#include "assess/snap_report.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace trisnap::test {
namespace {

using assess::Defect;

assess::SnapReport report_of(std::vector<assess::ReportedProblem> problems)
{
    assess::SnapReport report;
    report.path = "snap.json";
    report.problems = std::move(problems);
    return report;
}

AssessReport with_report(const std::vector<Item>& in, const std::vector<Item>& out, double t, const assess::SnapReport& report)
{
    AssessOptions options{t, "", 20};
    options.report = &report;
    return assess_items(in, out, options);
}

bool mentions(const std::vector<std::string>& failures, const std::string& what)
{
    for (const std::string& f : failures) {
        if (f.find(what) != std::string::npos) {
            return true;
        }
    }
    return false;
}

TEST(AssessExcuses, EachCodeExplainsOnlyWhatItSays)
{
    const assess::Excuses e(report_of({{5, 201, "collapsed_polygon", {}},
                                       {6, 102, "repeated_points", {}},
                                       {7, 209, "thin_part_collapsed", {}},
                                       {8, 207, "separation_not_reached", assess::Pt{1, 1}}}));
    EXPECT_EQ(e.explain(Defect::missing, 5), "201 collapsed_polygon");
    EXPECT_EQ(e.explain(Defect::missing, 6), "") << "removed repeated points do not explain a lost feature";
    EXPECT_EQ(e.explain(Defect::drift, 5), "") << "a collapse explains the loss, not a drift";
    EXPECT_EQ(e.explain(Defect::drift, 7), "209 thin_part_collapsed");
    EXPECT_EQ(e.explain(Defect::missing, 7), "") << "a thin part that collapsed leaves the rest of the feature";
    EXPECT_EQ(e.explain(Defect::gap, 1, 7), "209 thin_part_collapsed") << "either feature of the pair";
    EXPECT_EQ(e.explain_separation({1.5, 1}, {3, 3}, 1.0), "207 separation_not_reached");
    EXPECT_EQ(e.explain_separation({2.5, 1}, {3, 3}, 1.0), "") << "farther than T from the reported place";
    EXPECT_EQ(assess::Excuses().explain(Defect::missing, 5), "") << "no report, no excuse";
}

TEST(AssessExcuses, ACollapseInTheReportExcusesTheMissingFeature)
{
    const std::vector<Item> in{{1, square(0, 0, 1)}, {2, square(5, 0, 1)}};
    const std::vector<Item> out{{1, square(0, 0, 1)}};
    EXPECT_FALSE(assess_items(in, out, 0.1).contract_holds());
    const AssessReport excused = with_report(in, out, 0.1, report_of({{2, 201, "collapsed_polygon", {}}}));
    EXPECT_EQ(excused.n_missing, 1);
    EXPECT_EQ(excused.excused_counts.missing, 1);
    EXPECT_TRUE(excused.contract_holds()) << excused.contract_failures().front();
    ASSERT_EQ(excused.excused.size(), 1u);
    EXPECT_EQ(excused.excused[0].fid_a, 2);
    EXPECT_EQ(excused.excused[0].text, "missing");
    EXPECT_EQ(excused.excused[0].excused_by, "201 collapsed_polygon");
    const AssessReport wrong_code = with_report(in, out, 0.1, report_of({{2, 102, "repeated_points", {}}}));
    EXPECT_TRUE(mentions(wrong_code.contract_failures(), "1 missing"));
    const AssessReport wrong_fid = with_report(in, out, 0.1, report_of({{1, 201, "collapsed_polygon", {}}}));
    EXPECT_FALSE(wrong_fid.contract_holds()) << "the code must be on the lost feature";
}

TEST(AssessExcuses, AThinPartCodeExcusesDriftAndTheLostBoundary)
{
    // 1 and 2 share the edge x = 10; 1's output pulls back to x = 9: 10 T of drift and a new gap.
    const std::vector<Item> in{{1, square(0, 0, 10)}, {2, square(10, 0, 10)}};
    const std::vector<Item> out{{1, "POLYGON((0 0,9 0,9 10,0 10,0 0))"}, {2, square(10, 0, 10)}};
    const AssessReport bare = assess_items(in, out, 0.1);
    EXPECT_EQ(bare.gaps_new, 1);
    EXPECT_EQ(bare.n_drift, 1);
    EXPECT_TRUE(mentions(bare.contract_failures(), "1 new gaps"));
    EXPECT_TRUE(mentions(bare.contract_failures(), "1 features drift > 2T"));
    const AssessReport thin = with_report(in, out, 0.1, report_of({{1, 209, "thin_part_collapsed", {}}}));
    EXPECT_EQ(thin.excused_counts.gaps, 1);
    EXPECT_EQ(thin.excused_counts.drift, 1);
    EXPECT_TRUE(thin.contract_holds());
    const AssessReport collapse = with_report(in, out, 0.1, report_of({{1, 201, "collapsed_polygon", {}}}));
    EXPECT_EQ(collapse.excused_counts.total(), 0) << "201 explains a lost feature; feature 1 is there";
    EXPECT_FALSE(collapse.contract_holds());
}

TEST(AssessExcuses, ALostBoundaryCodeExcusesTheGapAndNotTheDrift)
{
    // 2's output pulls back to x = 11: a new gap (and drift) between two features still written.
    const std::vector<Item> in{{1, square(0, 0, 10)}, {2, square(10, 0, 10)}};
    const std::vector<Item> out{{1, square(0, 0, 10)}, {2, "POLYGON((11 0,20 0,20 10,11 10,11 0))"}};
    const AssessReport lost = with_report(in, out, 0.1, report_of({{2, 210, "shared_boundary_lost", {}}}));
    EXPECT_EQ(lost.excused_counts.gaps, 1);
    EXPECT_EQ(lost.excused_counts.drift, 0) << "210 says the boundary went, not how far the feature moved";
    EXPECT_TRUE(mentions(lost.contract_failures(), "1 features drift > 2T"));
    EXPECT_FALSE(mentions(lost.contract_failures(), "new gaps"));
    const assess::Excuses e(report_of({{2, 210, "shared_boundary_lost", {}}}));
    EXPECT_EQ(e.explain(Defect::gap, 1, 2), "210 shared_boundary_lost") << "on either feature of the pair";
    EXPECT_EQ(e.explain(Defect::missing, 2), "");
}

TEST(AssessExcuses, ASeparationBreachIsExcusedOnlyWhereTheReportPlacesIt)
{
    // Two squares 0.4 apart at T = 1: four vertices closer than T, four closer than T/2 to an edge.
    const std::vector<Item> out{{1, square(10, 0, 10)}, {2, "POLYGON((20.4 0,30 0,30 10,20.4 10,20.4 0))"}};
    const AssessReport one = with_report(out, out, 1.0, report_of({{1, 207, "separation_not_reached", assess::Pt{20, 0}}}));
    EXPECT_EQ(one.n_vv_breaches + one.n_ve_breaches, 8);
    EXPECT_EQ(one.excused_counts.separations, 4) << "the four breaches at y = 0";
    EXPECT_TRUE(mentions(one.contract_failures(), "4 separation breaches"));
    const AssessReport both = with_report(out, out, 1.0,
                                          report_of({{1, 207, "separation_not_reached", assess::Pt{20, 0}},
                                                     {2, 205, "not_converged", assess::Pt{20.4, 10}}}));
    EXPECT_EQ(both.excused_counts.separations, 8);
    EXPECT_TRUE(both.contract_holds());
}

TEST(AssessExcuses, OverlapsAndCrossingsTheInputHadAreNotNew)
{
    // 1 and 2 overlap (and their boundaries cross) in the input already; 3 is moved onto 1.
    const std::vector<Item> in{{1, square(0, 0, 2)}, {2, square(1, 1, 2)}, {3, square(10, 0, 1)}, {4, "LINESTRING(20 0,22 2,22 0,20 2)"}};
    AssessReport r = assess_items(in, in, 0.1);
    EXPECT_EQ(r.n_overlaps, 1);
    EXPECT_EQ(r.n_overlaps_new, 0);
    EXPECT_EQ(r.n_crossings, 3) << "two between 1 and 2, one where the line crosses itself";
    EXPECT_EQ(r.n_crossings_new, 0);
    EXPECT_TRUE(r.contract_holds()) << r.contract_failures().front();
    std::vector<Item> out = in;
    out[2] = {3, square(0.5, -0.5, 1)};
    r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_overlaps, 2);
    EXPECT_EQ(r.n_overlaps_new, 1);
    EXPECT_EQ(r.n_crossings_new, 2) << "3's boundary crosses 1's twice";
    EXPECT_TRUE(mentions(r.contract_failures(), "1 new overlaps"));
    EXPECT_TRUE(mentions(r.contract_failures(), "2 new crossings"));
}

TEST(AssessExcuses, CoordinatesThatCannotBeMeasuredAreInvalidNotACrash)
{
    const std::vector<Item> in{{1, square(0, 0, 1)}, {2, square(5, 0, 1)}};
    const std::vector<Item> out{{1, square(0, 0, 1)}, {2, "POLYGON((5 0,1e200 0,6 1,5 1,5 0))"}};
    const AssessReport r = assess_items(in, out, 0.1);
    EXPECT_EQ(r.n_unmeasurable, 1);
    EXPECT_EQ(r.n_invalid, 1);
    EXPECT_EQ(r.n_missing, 0) << "the feature is there, broken";
    EXPECT_TRUE(std::isfinite(r.area_change)) << "a 1e200 coordinate would make it 1e+199 %";
    EXPECT_FALSE(r.contract_holds());
    const nlohmann::json j = nlohmann::json::parse(assess_report_json(r));
    EXPECT_TRUE(j["examples"]["invalid"][0]["x"].is_null()) << "no place to give";
    EXPECT_EQ(j["examples"]["unmeasurable"][0]["fid"], 2);
}

} // namespace
} // namespace trisnap::test
