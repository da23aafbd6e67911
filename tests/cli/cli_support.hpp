#pragma once
// Helpers for the CLI tests: run the binary, make fixtures with GDAL, read results back and
// check them independently of trisnap's own code (GEOS validity through OGR, field equality,
// feature accounting against the JSON report).
#include <gdal_priv.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>

#include <cstdint>
#include <filesystem>
#include <csignal>
#include <functional>
#include <map>
#include <string>
#include <sys/types.h>
#include <vector>

namespace trisnap::test {

struct RunOutput {
    int code = -1;
    std::string out;
    std::string err;
    /// Lines of stderr (without the trailing newline).
    std::vector<std::string> err_lines() const;
};

/// A fresh directory, removed with everything in it at the end of the test.
class TempDir {
public:
    TempDir();
    ~TempDir();
    std::string path(const std::string& name) const { return (m_path / name).string(); }

private:
    std::filesystem::path m_path;
};

/// Runs the trisnap binary with `args`; stdout and stderr go through files in `dir`. The
/// environment variable TRISNAP_TEST_EXE replaces the binary (to see a test fail on an older one).
RunOutput run_trisnap(const TempDir& dir, const std::vector<std::string>& args);

/// Runs the trisnap binary with `args` and sends it `signal` (SIGKILL: `code` is 137) at the
/// first line it writes on stderr for which `stop(line)` holds.
RunOutput run_trisnap_killed_when(const TempDir& dir, const std::vector<std::string>& args,
                                  const std::function<bool(const std::string&)>& stop, int signal = SIGKILL);
/// Resource limits for one run (0 = unlimited).
struct Limits {
    long long file_size = 0;     ///< RLIMIT_FSIZE in bytes: "disk full" (SIGXFSZ ignored, writes fail)
    long long address_space = 0; ///< RLIMIT_AS in bytes: allocations fail
};

/// run_trisnap() in a child process with `limits` set (fork, setrlimit, exec: no shell).
RunOutput run_trisnap_limited(const TempDir& dir, const std::vector<std::string>& args, const Limits& limits);

/// Starts trisnap without waiting (stdout and stderr to files in `dir`); finish with wait_trisnap().
pid_t spawn_trisnap(const TempDir& dir, const std::vector<std::string>& args, const Limits& limits = {});
RunOutput wait_trisnap(const TempDir& dir, pid_t pid);

/// Waits until `pid` (spawned by spawn_trisnap) has stopped itself (SIGSTOP); false when it
/// ended instead (then wait_trisnap() must not be called: its status is gone).
bool wait_until_stopped(pid_t pid);

/// An environment variable set for the runs started while it lives (the children inherit it),
/// unset at the end: the test hooks TRISNAP_TEST_RAISE and TRISNAP_FAIL_TILES.
class ScopedEnv {
public:
    ScopedEnv(const std::string& name, const std::string& value);
    ~ScopedEnv();
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    std::string m_name;
};

/// Names in `dir` that contain ".trisnap-tmp" (temporary files or directories left behind).
std::vector<std::string> leftovers(const std::string& dir);

std::string data_dir();
std::string configs_dir();
bool exists(const std::string& path);

/// One feature to write into a fixture: WKT ("" = null geometry) and field values by name.
struct FixtureFeature {
    std::string wkt;
    std::map<std::string, std::string> fields;
    bool nan_coordinate = false; ///< replace the first x by NaN (WKT cannot say NaN)
};

/// Writes a one-layer fixture. Fields: id (Integer), big (Integer64), area (Real),
/// name (String), day (Date). `epsg` 0 = no CRS.
void write_fixture(const std::string& path, const std::string& driver, const std::string& layer,
                   int epsg, OGRwkbGeometryType type, const std::vector<FixtureFeature>& features);

/// snapping_fixture() as layer "parcels" (EPSG:3857, any geometry type) in dir/name; its path.
std::string write_snapping_gpkg(const TempDir& dir, const std::string& name = "in.gpkg");

/// Exit code `code`, nothing on stdout, exactly one line on stderr, "trisnap: error: ...",
/// containing `text`.
void expect_error(const RunOutput& r, int code, const std::string& text);

/// A small layer with what snapping is for: two squares 0.004 apart, a sliver, a line, a
/// polygon that collapses at t = 0.01, and UTF-8 names.
std::vector<FixtureFeature> snapping_fixture();

/// Everything read back from a layer: FID, the value of every field as text (null = "<null>"),
/// geometry validity and WKT.
struct ReadFeature {
    std::int64_t fid = -1;
    std::map<std::string, std::string> fields;
    bool has_geometry = false;
    bool valid = true;
    std::string wkt;
};
/// `bbox` (xmin, ymin, xmax, ymax) applies the same OGR spatial filter as `trisnap --bbox`.
std::vector<ReadFeature> read_layer(const std::string& path, const std::string& layer = "",
                                    const std::vector<double>& bbox = {});

/// The report file as JSON.
nlohmann::json read_json(const std::string& path);

/// The FIDs of features missing from `output` (by FID or orig_fid) that `report` excuses: only
/// a problem whose code means "not written" (problem_codes.hpp) excuses a missing feature.
std::vector<std::int64_t> missing_but_reported(const nlohmann::json& report, const std::vector<ReadFeature>& output);

/// Bytes of a file, for determinism checks.
std::string file_bytes(const std::string& path);

} // namespace trisnap::test
