#pragma once
// The two phases of a snap run that touch GDAL: reading the layer into the work store, and
// writing the stitched layer with the attributes read again. (The phases in between are
// stitch::TiledRun's.)
#include "app/interrupt.hpp"
#include "app/pipeline.hpp"
#include "app/plan.hpp"
#include "app/progress.hpp"
#include "stitch/output.hpp"
#include "stitch/spool.hpp"
#include "tiling/work_store.hpp"

#include <vector>

namespace trisnap {

/// One input feature in records.bin: its FID, what happened to it, its linear type (for the
/// output geometry's type).
struct RecordEntry {
    enum Verdict : std::uint8_t { pass = 0, snap = 1, rejected = 2 };
    static constexpr std::size_t k_bytes = 13;
    std::int64_t fid = 0;
    Verdict verdict = pass;
    std::uint32_t type = 0;
    void encode(char* out) const;
    static RecordEntry decode(const char* in);
};

inline const char* const k_records_file = "records.bin";

/// What the read phase leaves for the rest of the run (kept in the store as read.bin).
struct ReadSummary {
    std::size_t records = 0;        ///< features read (after --where/--bbox)
    std::size_t rejected = 0;       ///< not given to the engine and not written (NaN/inf)
    std::size_t input_vertices = 0; ///< of the snapped features, as GDAL counts them
    std::vector<Problem> problems;  ///< found while reading and cleaning (input FIDs)
    stitch::SpoolMeta meta;
};

/// Reads the layer once (geometries only; attributes are read again when writing) into
/// features.bin and records.bin (each input feature's FID, what happened to it, and its type).
/// Throws io_error for an empty layer or selection.
ReadSummary read_layer(Plan& plan, tiling::WorkStore& store, std::size_t sample_cap, std::size_t fid_buffer,
                       Progress& progress, const InterruptGuard& interrupt);

/// The read phase's summary from an earlier run of this work directory (false: it did not finish).
bool load_read(const tiling::WorkStore& store, ReadSummary& out);

/// Reads the layer again in step with records.bin and the stitched features, and writes every
/// feature in input order through `writer` (attributes and FIDs kept, geometry replaced by the
/// snapped one). Fills written/dropped/unwritable and appends the features' problems.
void write_layer(Plan& plan, const tiling::WorkStore& store, stitch::OutputMerger& merger, LayerWriter& writer,
                 RunResult& result, Progress& progress, const InterruptGuard& interrupt);

} // namespace trisnap
