#pragma once
// A cluster run's directory (RUN_DIR): the work directory of one snap run whose phases run as
// separate commands, on any machine that sees the directory (shared storage):
//   trisnap plan       makes it: manifest.json, the spooled features and tiles, cluster.json;
//   trisnap snap-tiles adds tile results (each committed by temp file + rename) and, when a
//                      task has done its share, shard-I-of-N;
//   trisnap stitch     merges and snaps again where seams disagree, and writes OUT.
// manifest.json is the work directory's manifest (run_manifest(): version, the input's files
// with sizes and times, layer, filters, every option that changes the output), the build that
// planned it ("build": build_id(), app/build_id.hpp), and a "cluster" object with what the later
// commands need without the original command line: the input's path, layer, filters and open
// options, the resolved settings as TOML, and the tolerance in layer units (exact) with how it
// was derived. Nothing in the directory is removed by trisnap, except the temporary files that
// killed tasks on this host left (remove_stale_temporaries()).
// Refused, with one line naming what differs (argument_error): a directory with no run, the
// work directory of a `trisnap snap` run, a run planned by another trisnap version or by another
// build of this version (the line names the build that planned it and the one running), a plan
// that did not finish, and (stitch) an input whose files changed since the plan.
#include "app/options.hpp"
#include "app/plan.hpp"
#include "app/work_dir.hpp"
#include "config/config.hpp"
#include "core/snap.hpp"
#include "stitch/layout.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace trisnap {

/// What `trisnap plan` learned, kept as cluster.json (its presence marks a finished plan).
struct PlanRecord {
    std::size_t tiles = 0;            ///< tiles that run (plan leaves holding features)
    std::uint64_t vertices = 0;       ///< input vertices of their buckets
    std::uint64_t largest = 0;        ///< input vertices of the largest tile
    std::size_t shards = 0;           ///< the number of shards recorded (--num-shards, else suggested)
    std::size_t suggested = 0;        ///< suggest_shards()
};

/// This machine's host name, as temporary file names and shard markers give it.
std::string host_name();

/// The manifest `trisnap plan` writes into RUN_DIR.
std::string cluster_manifest(const Plan& plan, const SnapArgs& args);

/// Commits cluster.json.
void save_plan_record(tiling::WorkStore& store, const PlanRecord& record);

class RunDir {
public:
    /// Attaches to a cluster run's directory and checks its manifest (see above).
    static RunDir open(const std::string& path);

    WorkDir& work() { return m_work; }
    const std::string& path() const { return m_work.path(); }
    /// The input, layer, filters and open options of the plan (input paths are absolute).
    const SnapArgs& input_args() const { return m_args; }
    /// The resolved settings of the plan.
    const Config& config() const { return m_config; }
    SnapOptions options() const;
    stitch::TilingOptions tiling() const;
    /// cluster.json; throws argument_error when the plan did not finish.
    const PlanRecord& record() const { return m_record; }
    /// The numbers of shards that finished tasks ran under (their shard-I-of-N files), ascending.
    std::vector<std::size_t> shard_counts_seen() const;
    /// Marks shard `index` of `count` finished.
    void mark_finished(std::size_t index, std::size_t count, const std::string& summary);
    /// Removes the temporary files (NAME.tmp-HOST-PID, tiling/work_store.hpp) that processes of
    /// this host which no longer run left behind (a task killed while writing a result); those of
    /// other hosts, or of a process still running here, are kept. Returns how many it removed.
    std::size_t remove_stale_temporaries();
    /// Throws argument_error unless `plan` (the input opened again) is the planned one: same
    /// files with the same sizes and times, layer, filters, tolerance and options.
    void check_input(const Plan& plan) const;

private:
    explicit RunDir(WorkDir work) : m_work(std::move(work)) {}
    void load_manifest();
    void load_record();

    WorkDir m_work;
    SnapArgs m_args;
    Config m_config;
    double m_tolerance = 0;
    std::string m_run_manifest; ///< the manifest without its "cluster" object
    PlanRecord m_record;
};

} // namespace trisnap
