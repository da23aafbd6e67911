// Absurd options: tolerances whose squares overflow or underflow, thread counts far beyond the
// cores, config integers that do not fit, config paths that are not files, an empty --bbox.
// Each is one line and an exit code, never a crash, a hang or a silently ignored value.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include <sys/stat.h>
#include <unistd.h>

namespace trisnap::test {
namespace {

class CliLimits : public ::testing::Test {
protected:
    /// A one-triangle GeoJSON layer (the reproduction).
    std::string triangle()
    {
        const std::string path = dir.path("triangle.geojson");
        write_fixture(path, "GeoJSON", "triangle", 0, wkbPolygon, {{"POLYGON ((0 0, 1 0, 0 1, 0 0))", {}}});
        return path;
    }

    std::string toml(const std::string& name, const std::string& text)
    {
        const std::string path = dir.path(name);
        std::ofstream(path) << text;
        return path;
    }

    /// Exit code `code`, nothing on stdout, exactly one line on stderr containing `text`.
    void expect_error(const RunOutput& r, int code, const std::string& text)
    {
        EXPECT_EQ(r.code, code) << r.err;
        EXPECT_EQ(r.out, "");
        ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
        EXPECT_EQ(r.err.rfind("trisnap: error: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
    }

    TempDir dir;
};

TEST_F(CliLimits, ToleranceWhoseSquareOverflowsIsRefused)
{
    // These crashed with a segmentation fault (exit 139), tiled or not.
    const std::string in = triangle();
    for (const char* t : {"1e308", "5e307", "1.7e308", "1e145"}) {
        for (bool tiles : {true, false}) {
            std::vector<std::string> args{"snap", in, dir.path("out.gpkg"), "--tolerance", t};
            if (!tiles) {
                args.push_back("--no-tiles");
            }
            SCOPED_TRACE(std::string("t=") + t + (tiles ? " tiled" : " --no-tiles"));
            expect_error(run_trisnap(dir, args), 2,
                         "is out of range [3.20333e-145, 3.12175e+144]: its square and multiples would overflow");
            EXPECT_FALSE(exists(dir.path("out.gpkg")));
        }
    }
    expect_error(run_trisnap(dir, {"snap", "--config", toml("huge.toml", "[snap]\ntolerance = 1e308\n"),
                                   "--print-config"}),
                 2, "huge.toml: tolerance 1e+308 is out of range [");
}

TEST_F(CliLimits, ToleranceWhoseSquareUnderflowsIsRefused)
{
    // A 1e-200 square at t = 1e-202: t*t underflows to 0, so the square was dropped as
    // "thinner than the tolerance" (201). It is refused instead: comparisons of squared
    // distances with t*t cannot be made at that scale.
    const std::string in = dir.path("tiny.geojson");
    write_fixture(in, "GeoJSON", "tiny", 0, wkbPolygon, {{"POLYGON ((0 0, 1e-200 0, 1e-200 1e-200, 0 1e-200, 0 0))", {}}});
    const std::string message = "tolerance 1e-202 is out of range [3.20333e-145, 3.12175e+144]: its square and "
                                "multiples would underflow double precision";
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "1e-202"}), 2, message);
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "1e-202", "--no-tiles"}), 2,
                 message);
    // In metres on a geographic layer the converted tolerance is checked the same way.
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance-m", "1e-200"}), 2,
                 "is out of range [3.20333e-145, 3.12175e+144]");
}

TEST_F(CliLimits, HaloThatOverflowsIsRefused)
{
    // halo x t x 2^max_growth sizes each tile's box and frame; it must stay a finite double at
    // every accepted t (the tiling code never checked), so the halo factor is bounded too.
    expect_error(run_trisnap(dir, {"snap", triangle(), dir.path("out.gpkg"), "--tolerance", "0.01", "--halo", "1e300"}),
                 2, "tiling.halo must be in [2, 1048576]");
    EXPECT_FALSE(exists(dir.path("out.gpkg")));
}

TEST_F(CliLimits, ThreadsBeyondTheCoresAreClampedWithOneWarning)
{
    // --threads 10000 spawned thousands of threads and ran for minutes.
    const unsigned cores = std::thread::hardware_concurrency();
    const auto start = std::chrono::steady_clock::now();
    // (GeoJSON is in degrees: a tolerance under 0.001 draws no other warning.)
    const RunOutput r = run_trisnap(dir, {"snap", triangle(), dir.path("out.gpkg"), "--tolerance", "1e-4",
                                          "--threads", "10000"});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_EQ(r.err_lines()[0].rfind("trisnap: warning: threads 10000 is more than the ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("; using "), std::string::npos) << r.err;
    EXPECT_LT(seconds, 60.0);
    const RunOutput printed = run_trisnap(dir, {"snap", "--threads", "10000", "--print-config"});
    EXPECT_EQ(printed.code, 0);
    EXPECT_EQ(printed.out.find("threads = 10000"), std::string::npos) << printed.out;
    const RunOutput fits = run_trisnap(dir, {"snap", "--threads", std::to_string(cores), "--print-config"});
    EXPECT_EQ(fits.err, "");
}

TEST_F(CliLimits, ConfigIntegersThatDoNotFitAreErrors)
{
    // threads = 4294967297 wrapped to 1.
    const std::string threads = toml("threads.toml", "# wraps\n[run]\nthreads = 4294967297\n");
    expect_error(run_trisnap(dir, {"snap", "--config", threads, "--print-config"}), 2,
                 threads + ":3: key 'run.threads': 4294967297 is out of range");
    const std::string growth = toml("growth.toml", "[tiling]\nmax_growth = -4294967296\n");
    expect_error(run_trisnap(dir, {"snap", "--config", growth, "--print-config"}), 2,
                 growth + ":2: key 'tiling.max_growth': -4294967296 is out of range");
    // Beyond 64 bits TOML itself cannot hold the value: a syntax error at its line.
    const std::string ops = toml("ops.toml", "[snap]\nmax_operations = 99999999999999999999\n");
    expect_error(run_trisnap(dir, {"snap", "--config", ops, "--print-config"}), 2, ops + ":2:");
    const std::string budget = toml("budget.toml", "[tiling]\nvertex_budget = -1\n");
    expect_error(run_trisnap(dir, {"snap", "--config", budget, "--print-config"}), 2, "vertex_budget must be >= 16");
}

TEST_F(CliLimits, ConfigPathMustBeAReadableFile)
{
    // A directory and /dev/zero were read as an empty config.
    expect_error(run_trisnap(dir, {"snap", "--settings", dir.path(""), "--print-config"}), 2, "is a directory");
    expect_error(run_trisnap(dir, {"snap", "--settings", "/dev/zero", "--print-config"}), 2,
                 "/dev/zero: not a regular file");
    expect_error(run_trisnap(dir, {"snap", "--settings", dir.path("absent.toml"), "--print-config"}), 2,
                 "absent.toml: no such file");
    const std::string nul = dir.path("nul.toml");
    std::ofstream(nul, std::ios::binary) << std::string("[snap]\0tolerance = 1\n", 21);
    expect_error(run_trisnap(dir, {"snap", "--settings", nul, "--print-config"}), 2, "NUL byte");
}

TEST_F(CliLimits, NonAsciiConfigIsAnErrorNamingItsLine)
{
    // toml++ 3.3 hits undefined behaviour on some non-ASCII characters (fuzz_config).
    const std::string path = toml("utf8.toml", "[snap]\n# tol\xc3\xa9rance\ntolerance = 1\n");
    expect_error(run_trisnap(dir, {"snap", "--config", path, "--print-config"}), 2,
                 path + ":2: non-ASCII character: config files must be ASCII");
}

TEST_F(CliLimits, ConfigWithoutReadPermissionIsAnError)
{
    if (geteuid() == 0) {
        GTEST_SKIP() << "running as root: a file without read permission is still readable";
    }
    const std::string locked = toml("locked.toml", "[snap]\ntolerance = 1\n");
    chmod(locked.c_str(), 0);
    expect_error(run_trisnap(dir, {"snap", "--config", locked, "--print-config"}), 2, "cannot read");
}

TEST_F(CliLimits, EmptyBboxIsAnError)
{
    // --bbox "" used to mean "no filter".
    const std::string in = triangle();
    expect_error(run_trisnap(dir, {"snap", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--bbox", ""}), 2,
                 "--bbox must be xmin,ymin,xmax,ymax");
    expect_error(run_trisnap(dir, {"validate", in, dir.path("out.gpkg"), "--tolerance", "0.01", "--bbox", ""}), 2,
                 "--bbox");
    expect_error(run_trisnap(dir, {"render", in, "-o", dir.path("x.svg"), "--bbox", ""}), 2, "--bbox");
}

} // namespace
} // namespace trisnap::test
