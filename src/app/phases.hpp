#pragma once
// The two phases of a snap run that touch GDAL: reading the layer into the work store, and
// writing the stitched layer with the attributes read again. (The phases in between are
// stitch::TiledRun's.)
#include "app/interrupt.hpp"
#include "app/pipeline.hpp"
#include "app/problem_log.hpp"
#include "app/plan.hpp"
#include "app/progress.hpp"
#include "stitch/output.hpp"
#include "stitch/spool.hpp"
#include "tiling/work_store.hpp"

#include <vector>

namespace trisnap {

/// One input feature in records.bin: its FID, what happened to it, whether the read reported a
/// problem for it, its linear type (for the output geometry's type).
struct RecordEntry {
    enum Verdict : std::uint8_t { pass = 0, snap = 1, rejected = 2 };
    static constexpr std::size_t k_bytes = 13;
    std::int64_t fid = 0;
    Verdict verdict = pass;
    bool problem = false; ///< stored in the verdict's byte (bit 7)
    std::uint32_t type = 0;
    void encode(char* out) const;
    static RecordEntry decode(const char* in);
};

inline const char* const k_records_file = "records.bin";

/// What the read phase found in one input layer. records.bin holds the layers one after the
/// other, in --layer order: the first `records` entries are layer 0's, and so on.
struct LayerRead {
    std::uint64_t records = 0;        ///< features read (after --where/--bbox)
    std::uint64_t rejected = 0;       ///< not given to the engine and not written (NaN/inf)
    std::uint64_t input_vertices = 0; ///< of the snapped features
    std::uint64_t snapped = 0;        ///< given to the engine
    std::uint64_t problems = 0;       ///< its problems (ReadSummary::problems.in_layer())
    bool fids_unique = true;          ///< its FIDs are unique within it: its output keeps them
};

/// What the read phase leaves for the rest of the run (kept in the store as read.bin).
struct ReadSummary {
    std::size_t records = 0;        ///< features read (after --where/--bbox)
    std::size_t smaller = 0;        ///< snapped features smaller than the tolerance (checked, not kept)
    std::size_t rejected = 0;       ///< not given to the engine and not written (NaN/inf)
    std::size_t input_vertices = 0; ///< of the snapped features, as GDAL counts them
    ProblemLog problems;            ///< found while reading and cleaning (input FIDs), sealed
    stitch::SpoolMeta meta;
    std::vector<LayerRead> layers;  ///< per input layer, in --layer order
};

/// What the read phase holds in memory at most: the plan's vertex sample (a second reader,
/// app/read_phase.cpp, keeps one more of its own), the FIDs sorted at once by the uniqueness
/// check, the problems buffered before they go to the store.
struct ReadBuffers {
    std::size_t sample_vertices = 0;
    std::size_t fids = 0;
    std::size_t problem_bytes = 0;
    /// The last part of a large layer may be read at once on another thread (app/read_phase.cpp),
    /// kept in memory, or out of core in files of the store. Its sample (up to sample_vertices
    /// more), connection, buffers and heap stay resident after it (freed, kept for reuse), so
    /// the tiles' share of a limit would shrink by ~20-30 MiB: not under a limit below 512 MiB
    /// (Andorra x43 under 180 MiB: the read peaked at 111-122 MiB instead of 89-94, 8 MiB left for
    /// tiles; the run took 422 s instead of 3.6 while tiles were sized to a thread's share of
    /// that, stitch::pool_tile_vertices now gives them the whole of it, one at a time).
    bool second_reader = true;
};

/// Reads the layers once, one after the other (geometries only; attributes are read again when
/// writing) into features.bin and records.bin (each input feature's FID, what happened to it,
/// and its type) and the problems into runs of the store; input positions run on across layers.
/// Throws io_error when nothing is read.
ReadSummary read_layer(Plan& plan, tiling::WorkStore& store, const ReadBuffers& buffers, Progress& progress,
                       const InterruptGuard& interrupt);

/// What `validate` reads of the input: the read phase's read, without the work store.
struct InputSurvey {
    std::vector<std::size_t> features; ///< per input layer, after --where/--bbox
    std::size_t vertices = 0;          ///< of every feature, as `trisnap info` counts them
    std::size_t smaller = 0;           ///< snapped features smaller than the tolerance
    std::size_t total() const;
};

/// Reads the layers as read_layer() does (the same reader: OSM interleaved) and counts.
InputSurvey survey_input(Plan& plan);

/// What the read phase stops on before anything is snapped, for `snap`, `plan` and `validate`
/// alike: no feature to snap (io_error), or the collapse guard's pre-check on the features
/// smaller than the tolerance (argument_error, app/collapse_guard.hpp).
void check_read(const Plan& plan, std::size_t features, std::size_t smaller);

/// The read phase's summary from an earlier run of this work directory (false: it did not finish);
/// its problems stay in the store, read back from there.
bool load_read(tiling::WorkStore& store, std::size_t problem_bytes, ReadSummary& out);

/// Reads the layers again in step with records.bin and the stitched features, and writes every
/// feature in input order through `writer`, layer k to the writer's layer k (attributes and
/// FIDs kept, geometry replaced by the snapped one). Fills written/dropped/unwritable, in total
/// and per layer, and adds the features' problems to the result's log (a phase of its own).
void write_layer(Plan& plan, const tiling::WorkStore& store, stitch::OutputMerger& merger, LayerWriter& writer,
                 RunResult& result, Progress& progress, const InterruptGuard& interrupt);

} // namespace trisnap
