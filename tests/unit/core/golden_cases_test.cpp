// Golden cases from tests/cases/<name>/ (see tests/cases/README.md): the engine's output must
// match expected.wkt after normalising, report exactly expected_problems.txt, keep the contract,
// and give the same answer for the input in reverse order.
// TRISNAP_UPDATE_GOLDEN=1 writes expected.wkt and expected_problems.txt from the engine instead
// of comparing: inspect every changed file by hand before committing it.
#include "golden_case.hpp"
#include "snap_harness.hpp"
#include "test_data.hpp"

#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

namespace trisnap {
namespace {

bool update_mode() {
    const char* v = std::getenv("TRISNAP_UPDATE_GOLDEN");
    return v && std::strcmp(v, "1") == 0;
}

std::vector<Feature> outputs(const SnapResult& r) {
    std::vector<Feature> out;
    for (const FeatureOutput& f : r.features)
        out.push_back({f.id, f.geometry});
    return out;
}

std::string case_name(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

/// How many features the case's expected_problems.txt flags with a drift code: the case states
/// exactly what the engine may flag, so that is its allowance.
std::size_t expected_flagged(const GoldenCase& c) {
    std::istringstream lines(c.expected_problems);
    std::set<std::int64_t> ids;
    std::int64_t id = 0;
    int code = 0;
    while (lines >> id >> code) {
        const std::vector<int>& drift = drift_codes();
        if (std::find(drift.begin(), drift.end(), code) != drift.end()) {
            ids.insert(id);
        }
    }
    return ids.size();
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, MatchesExpectedAndKeepsContract) {
    const GoldenCase c = read_golden_case(TRISNAP_TEST_CASES, GetParam());
    const CheckedRun run = snap_and_check(c.input, options_at(c.tolerance), expected_flagged(c));
    const std::vector<Feature> actual = outputs(run.result);
    const std::string problems = problem_lines(run.result.problems);
    if (update_mode()) {
        write_golden_expected(c, actual, problems);
        std::cout << "[updated] " << c.name << ": inspect " << c.dir.string() << "\n";
    } else {
        ASSERT_TRUE(c.has_expected) << c.dir << ": no expected.wkt; run with TRISNAP_UPDATE_GOLDEN=1";
        const double tol = 1e-9 * input_scale(c.input);
        EXPECT_EQ(geometry_difference(c.expected, actual, tol), "");
        EXPECT_EQ(problems, c.expected_problems);
    }
    EXPECT_TRUE(contract_holds(run.report, c.tolerance));
}

TEST_P(Golden, ReversedInputGivesTheSameOutput) {
    const GoldenCase c = read_golden_case(TRISNAP_TEST_CASES, GetParam());
    std::vector<Feature> reversed(c.input.rbegin(), c.input.rend());
    const SnapResult a = snap(c.input, options_at(c.tolerance));
    const SnapResult b = snap(reversed, options_at(c.tolerance));
    EXPECT_EQ(output_by_id(a), output_by_id(b));
    EXPECT_EQ(problem_lines(a.problems), problem_lines(b.problems));
}

INSTANTIATE_TEST_SUITE_P(Cases, Golden,
                         ::testing::ValuesIn(golden_case_names(TRISNAP_TEST_CASES)), case_name);

// A suite that finds no case must fail, not pass with nothing run (a wrong TRISNAP_TEST_CASES
// or a moved folder). GoogleTest also fails an uninstantiated parameterised suite on its own.
TEST(GoldenSuite, FindsItsCases) {
    const std::vector<std::string> names = golden_case_names(TRISNAP_TEST_CASES);
    EXPECT_FALSE(names.empty()) << "no golden case (a folder with input.wkt) in " << TRISNAP_TEST_CASES;
}

} // namespace
} // namespace trisnap
