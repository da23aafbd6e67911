// Configuration: presets load, flags beat the file, unknown keys name file:line, --print-config.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace trisnap::test {
namespace {

TEST(CliConfig, EveryPresetLoadsAndPrints)
{
    TempDir dir;
    for (const char* name : {"default", "osm-buildings", "landuse-coverage", "laptop"}) {
        const RunOutput r = run_trisnap(dir, {"snap", "--config", configs_dir() + "/" + name + ".toml", "--print-config"});
        EXPECT_EQ(r.code, 0) << name << ": " << r.err;
        EXPECT_EQ(r.err, "") << name;
        EXPECT_NE(r.out.find("[snap]"), std::string::npos) << name;
        EXPECT_NE(r.out.find("[run]"), std::string::npos) << name;
    }
}

TEST(CliConfig, FlagsBeatTheFileAndTheOutputReadsBack)
{
    TempDir dir;
    const std::string file = dir.path("c.toml");
    std::ofstream(file) << "[snap]\ntolerance = 0.5\nsliver_factor = 0.25\n[run]\nthreads = 2\n";
    RunOutput r = run_trisnap(dir, {"snap", "--config", file, "--threads", "1", "--tolerance", "0.1", "--print-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("tolerance = 0.1\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("sliver_factor = 0.25\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("threads = 1\n"), std::string::npos) << r.out;
    const std::string printed = dir.path("printed.toml");
    std::ofstream(printed) << r.out;
    const RunOutput again = run_trisnap(dir, {"snap", "--config", printed, "--print-config"});
    EXPECT_EQ(again.out, r.out);
}

TEST(CliConfig, UnknownKeyNamesFileLineAndKey)
{
    TempDir dir;
    const std::string file = dir.path("typo.toml");
    std::ofstream(file) << "# comment\n[snap]\ntolerance = 1\ntolerence = 2\n";
    const RunOutput r = run_trisnap(dir, {"snap", "in.gpkg", "out.gpkg", "--config", file});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err, "trisnap: error: " + file + ":4: key 'snap.tolerence': unknown key\n");
}

TEST(CliConfig, BadValuesAndSyntax)
{
    TempDir dir;
    const std::string wrong_type = dir.path("type.toml");
    std::ofstream(wrong_type) << "[run]\nthreads = \"many\"\n";
    RunOutput r = run_trisnap(dir, {"snap", "--config", wrong_type, "--print-config"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find(wrong_type + ":2: key 'run.threads': wrong type"), std::string::npos) << r.err;
    const std::string section = dir.path("section.toml");
    std::ofstream(section) << "[tiles]\nsize = 3\n";
    r = run_trisnap(dir, {"snap", "--config", section, "--print-config"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find(section + ":1: key 'tiles': unknown section"), std::string::npos) << r.err;
    const std::string range = dir.path("range.toml");
    std::ofstream(range) << "[snap]\nedge_separation = 3\n";
    r = run_trisnap(dir, {"snap", "--config", range, "--print-config"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("edge_separation must be in (0, 1]"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"snap", "--config", dir.path("absent.toml"), "--print-config"});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
}

TEST(CliConfig, BadFlagsAreOneLine)
{
    TempDir dir;
    RunOutput r = run_trisnap(dir, {"snap", "a.gpkg", "b.gpkg", "--tolerance", "abc"});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
    r = run_trisnap(dir, {"snap", "a.gpkg", "b.gpkg", "--tolerance", "1", "--progress", "sometimes"});
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
    r = run_trisnap(dir, {"frobnicate"});
    EXPECT_EQ(r.code, 2);
    r = run_trisnap(dir, {"--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("snap"), std::string::npos);
}

} // namespace
} // namespace trisnap::test
