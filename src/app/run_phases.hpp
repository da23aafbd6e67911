#pragma once
// The phases of a snap run as separate steps over one work store, so that `trisnap snap` runs
// them all in one process (run_pipeline) and a cluster run splits them across processes and
// machines: `plan` (read, spool), `snap-tiles` (snap a share of the tiles), `stitch` (the
// tiles merged at seams, the seam check, the write). Every phase leaves its files committed in
// the store, so the phases of one run give the same files, and the same output bytes, whether
// one process runs them or many. The result gathers counts, timings and problems as it goes.
// Errors: io_error for I/O and an empty selection; argument_error when the memory limit is too
// small for a tile (naming the tile and the smallest limit that works) or the data made an
// option unusable (a tile size too small for the extent).
#include "app/budget.hpp"
#include "app/interrupt.hpp"
#include "app/phases.hpp"
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "app/progress.hpp"
#include "app/work_dir.hpp"
#include "stitch/tiled_snap.hpp"

#include <functional>
#include <memory>

namespace trisnap {

class RunPhases {
public:
    /// `interrupt` is the command's: it lives from the command's start to its end, past the
    /// final rename, so a signal at any moment of the run stops it the same way.
    RunPhases(WorkDir& work, const RunBudget& budget, Progress& progress, InterruptGuard& interrupt,
              const SnapOptions& options, const stitch::TilingOptions& tiling);
    ~RunPhases();
    RunPhases(const RunPhases&) = delete;
    RunPhases& operator=(const RunPhases&) = delete;

    /// Phase "plan": reads the layer into the store (a resumed run takes it from the store),
    /// then checks that the disk holds the rest of the work files.
    void read(Plan& plan);
    /// The read phase's summary as an earlier process left it in the store; false when that
    /// process did not get so far. When the tile plan is there too, the plan's vertex sample
    /// is dropped (only the plan needs it).
    bool load_read();
    /// Creates the tiled run; with a memory limit, the tiles in flight share what the limit
    /// leaves beside what the process holds now.
    void open_tiles();
    /// Phase "spool": the tile plan and the buckets, or the store's when they are there.
    void spool();
    /// Phase "snap": the tiles without a result that `mine` selects (all of them without it).
    void snap(const std::function<bool(std::size_t)>& mine = {});
    /// Phase "stitch": the seam check; tiles that disagree are merged and snapped again.
    void stitch();
    /// Phase "write": the stitched features with the layers' attributes, in input order, then
    /// OUT closed (its files staged in the plan's commit group, or its transaction committed).
    void write(Plan& plan, LayerWriter& writer);

    /// What an interrupt (SIGINT, SIGTERM) between features or tiles reports.
    void set_interrupt_message(const char* message);

    stitch::TiledRun& tiles();
    RunResult& result();
    /// The result, its problems sealed (read back in order: by layer, FID, then code).
    RunResult finish();

private:
    template <class F>
    void phase(const char* name, F&& body);
    template <class F>
    void guarded(F&& body) const;
    std::uint64_t memory_pool() const;
    [[noreturn]] void too_small(const stitch::budget_error& e) const;
    std::string smallest_limit_text(std::uint64_t rss, std::uint64_t tile) const;
    std::size_t problem_buffer() const;
    void take_read(ReadSummary& summary);

    WorkDir& m_work;
    const RunBudget& m_budget;
    Progress& m_progress;
    SnapOptions m_options;
    stitch::TilingOptions m_tiling;
    RunResult m_result;
    InterruptGuard& m_interrupt;
    stitch::MemoryModel m_model;
    std::string m_small_tiles; ///< the warning when the limit made the tiles smaller than asked
    stitch::SpoolMeta m_meta;
    std::unique_ptr<stitch::TiledRun> m_run;
};

} // namespace trisnap
