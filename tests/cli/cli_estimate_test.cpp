// One estimator (issue 14): `info` and `validate` print the same estimate of a snap run for the
// same layer and settings, and the memory budget `snap` decides with is the one `validate` shows.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <utility>
#include <vector>

namespace trisnap::test {
namespace {

/// The text after `prefix` on the first line of `out` that starts with it ("" if none).
std::string line_after(const std::string& out, const std::string& prefix)
{
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.rfind(prefix, 0) == 0) {
            return line.substr(prefix.size());
        }
    }
    return "";
}

/// The estimates `info` prints for a layer: the default settings, then --no-tiles.
std::pair<std::string, std::string> info_estimates(const RunOutput& info)
{
    const std::string tiled = line_after(info.out, "  snap:     ");
    const std::size_t at = info.out.find(tiled) + tiled.size() + 1;
    const std::string rest = info.out.substr(at);
    return {tiled, line_after(rest, "            ")};
}

/// The byte count in validate's "memory:" line ("... 123 bytes before the input is opened").
unsigned long long budget_bytes(const RunOutput& validate)
{
    const std::string line = line_after(validate.out, "memory:    ");
    const std::size_t end = line.rfind(" bytes before");
    const std::size_t start = line.rfind(' ', end - 1) + 1;
    return end == std::string::npos ? 0 : std::stoull(line.substr(start, end - start));
}

class CliEstimate : public ::testing::Test {
protected:
    TempDir dir;
};

TEST_F(CliEstimate, InfoAndValidatePrintTheSameEstimate)
{
    const std::string in = write_snapping_gpkg(dir);
    const RunOutput info = run_trisnap(dir, {"info", in});
    ASSERT_EQ(info.code, 0) << info.err;
    const auto [tiled, untiled] = info_estimates(info);
    ASSERT_NE(tiled.find("vertices, "), std::string::npos) << info.out;
    ASSERT_NE(untiled.find("--no-tiles"), std::string::npos) << info.out;

    const RunOutput validate = run_trisnap(dir, {"validate", in, dir.path("out.gpkg"), "--tolerance", "0.5"});
    ASSERT_EQ(validate.code, 0) << validate.err;
    EXPECT_EQ(line_after(validate.out, "estimate:  "), tiled) << validate.out;

    const RunOutput single =
        run_trisnap(dir, {"validate", in, dir.path("out.gpkg"), "--tolerance", "0.5", "--no-tiles"});
    ASSERT_EQ(single.code, 0) << single.err;
    EXPECT_EQ(line_after(single.out, "estimate:  "), untiled) << single.out;
}

TEST_F(CliEstimate, ValidateShowsTheBudgetTheRunReports)
{
    const std::string in = write_snapping_gpkg(dir);
    const std::vector<std::string> command = {in, dir.path("out.gpkg"), "--tolerance", "0.5", "--threads", "1"};
    std::vector<std::string> validate_args = {"validate"};
    validate_args.insert(validate_args.end(), command.begin(), command.end());
    const RunOutput validate = run_trisnap(dir, validate_args);
    ASSERT_EQ(validate.code, 0) << validate.err;
    const unsigned long long bytes = budget_bytes(validate);
    ASSERT_GT(bytes, 0u) << validate.out;
    EXPECT_NE(line_after(validate.out, "memory:    ").find("in memory"), std::string::npos) << validate.out;

    std::vector<std::string> snap_args = {"snap"};
    snap_args.insert(snap_args.end(), command.begin(), command.end());
    snap_args.insert(snap_args.end(), {"--report", dir.path("report.json"), "-q"});
    const RunOutput snap = run_trisnap(dir, snap_args);
    ASSERT_EQ(snap.code, 0) << snap.err;
    const nlohmann::json memory = read_json(dir.path("report.json")).at("memory");
    EXPECT_EQ(memory.at("estimate_bytes").get<unsigned long long>(), bytes);
    EXPECT_EQ(memory.at("mode"), "in_memory");
}

TEST_F(CliEstimate, ValidateEstimatesTheFilteredLayer)
{
    const std::string in = write_snapping_gpkg(dir);
    const std::vector<std::string> command = {"validate", in, dir.path("out.gpkg"), "--tolerance", "0.001"};
    const RunOutput all = run_trisnap(dir, command);
    std::vector<std::string> filtered = command;
    filtered.insert(filtered.end(), {"--where", "id = 1"});
    const RunOutput one = run_trisnap(dir, filtered);
    ASSERT_EQ(all.code, 0) << all.err;
    ASSERT_EQ(one.code, 0) << one.err;
    // The square of feature 1 has 5 vertices (ring closed); the layer has more.
    EXPECT_EQ(line_after(one.out, "estimate:  ").find("(5 vertices, "), line_after(one.out, "estimate:  ").find('(')) << one.out;
    EXPECT_EQ(line_after(all.out, "estimate:  ").find("(5 vertices, "), std::string::npos) << all.out;
}

TEST_F(CliEstimate, SameOnNaturalEarthLand)
{
    const std::string in = data_dir() + "/natural_earth/natural_earth.gpkg";
    if (!exists(in)) {
        GTEST_SKIP() << "no " << in;
    }
    const RunOutput info = run_trisnap(dir, {"info", in, "--layer", "ne_10m_land"});
    ASSERT_EQ(info.code, 0) << info.err;
    const RunOutput validate = run_trisnap(
        dir, {"validate", in, dir.path("out.gpkg"), "--layer", "ne_10m_land", "--tolerance-m", "1", "--allow-collapse"});
    ASSERT_EQ(validate.code, 0) << validate.err;
    const std::string estimate = line_after(validate.out, "estimate:  ");
    EXPECT_EQ(estimate, info_estimates(info).first);
    EXPECT_NE(estimate.find("411137 vertices"), std::string::npos) << estimate;
}

} // namespace
} // namespace trisnap::test
