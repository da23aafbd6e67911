// One assembler: every golden case (tests/cases/<name>/) snapped untiled, where polygons come
// from the triangulation's faces, and tiled in tiles small enough that seams cut its features,
// where a cut feature is rebuilt from the directed edges its tiles own, gives the same
// geometry bit for bit (full-precision WKT) and the same problems (seam notes aside). Several
// plans per case: regular grids of a half, a third and a fifth of the case's extent, and
// balanced plans of 2 to 8 vertices a tile (their seams run through input vertices). The suite
// fails when it finds no case, or when no feature of any case was cut and rebuilt from edges.
#include "golden_case.hpp"
#include "test_data.hpp"
#include "tiled_check.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <sstream>

namespace trisnap {
namespace {

struct Tiling {
    std::string name;
    stitch::TilingOptions options;
};

std::vector<Tiling> tilings_for(const GoldenCase& c)
{
    std::vector<Tiling> out;
    const double scale = input_scale(c.input);
    for (int parts : {2, 3, 5}) {
        // A grid anchored at multiples of its size: an odd factor keeps the seams off the
        // round coordinates most cases use, an even one puts them there.
        out.push_back({"grid extent/" + std::to_string(parts), tiles_of(scale / parts, 1)});
    }
    for (std::size_t budget : {2u, 4u, 8u}) {
        stitch::TilingOptions t;
        t.plan.vertex_budget = budget;
        t.threads = 1;
        out.push_back({"balanced " + std::to_string(budget) + " vertices", t});
    }
    return out;
}

std::string first_difference(const SnapResult& untiled, const SnapResult& tiled)
{
    const auto a = output_by_id(untiled);
    const auto b = output_by_id(tiled);
    for (const auto& [id, wkt] : a) {
        const auto it = b.find(id);
        if (it == b.end() || it->second != wkt) {
            std::ostringstream s;
            s << "id " << id << "\n  untiled " << wkt << "\n  tiled   " << (it == b.end() ? "(missing)" : it->second);
            return s.str();
        }
    }
    return a.size() == b.size() ? "" : "the tiled run has features the untiled one has not";
}

TEST(AssembleGolden, TiledEqualsUntiledOnEveryCase)
{
    const std::vector<std::string> names = golden_case_names(TRISNAP_TEST_CASES);
    ASSERT_GT(names.size(), 10u) << "no golden cases found in " << TRISNAP_TEST_CASES;
    std::size_t assembled = 0;
    std::size_t cases_cut = 0;
    for (const std::string& name : names) {
        const GoldenCase c = read_golden_case(TRISNAP_TEST_CASES, name);
        const SnapOptions options = options_at(c.tolerance);
        const SnapResult untiled = snap(c.input, options);
        std::size_t case_assembled = 0;
        for (const Tiling& t : tilings_for(c)) {
            SCOPED_TRACE(name + ", " + t.name);
            const stitch::TiledResult tiled = stitch::snap_tiled(c.input, options, t.options);
            EXPECT_EQ(first_difference(untiled, tiled.result), "");
            EXPECT_EQ(problems_without_seams(untiled.problems), problems_without_seams(tiled.result.problems));
            case_assembled += tiled.stitch.assembled_features;
        }
        assembled += case_assembled;
        cases_cut += case_assembled > 0 ? 1 : 0;
        std::cout << "[ golden  ] " << name << ": " << case_assembled << " features rebuilt from tile edges\n";
    }
    EXPECT_GT(assembled, 0u) << "no feature of any case was cut by a seam: the test compared nothing assembled";
    EXPECT_GE(2 * cases_cut, names.size()) << "seams cut features in only " << cases_cut << " of " << names.size()
                                           << " cases";
}

} // namespace
} // namespace trisnap
