#pragma once
// The stitched layer, feature by feature in input order: a k-way merge of the final tiles'
// results (each in input order) in step with features.bin. A feature one tile had whole and
// owns entirely is copied; any other is rebuilt from the edges its tiles own by the one
// assembler (core/assemble.hpp), so it is the feature an untiled run traces. Per-feature
// outcomes (201-204, 206, 208, and 210 from the tiles' evidence) are judged here, on the stitched feature.
// Memory: one record buffer per result file (merged in rounds when there are many files) and
// the current feature.
#include "core/snap.hpp"
#include "stitch/layout.hpp"
#include "stitch/spool.hpp"
#include "stitch/tile_result.hpp"

#include <memory>
#include <vector>

namespace trisnap::stitch {

struct OutputItem {
    std::uint64_t seq = 0;          ///< the feature's input position
    FeatureOutput output;           ///< id: the input FID
    std::vector<Problem> problems;  ///< feature_id: the input FID
};

struct OutputCounts {
    std::size_t copied = 0;    ///< taken whole from one tile
    std::size_t assembled = 0; ///< rebuilt from the edges of several tiles
    std::size_t failed = 0;    ///< not written: a tile they met failed (303)
    SnapStats stats;           ///< the tiles' engine counters summed, per-feature counts global
};

class OutputMerger {
public:
    OutputMerger(tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, const SpoolMeta& meta,
                 const SnapOptions& options);
    /// Problems about the tiling (301, 302), keyed by the rank of their feature (any order);
    /// given before the first next().
    void set_notes(std::vector<std::pair<std::uint64_t, Problem>> notes);
    ~OutputMerger();
    /// The next spooled feature's output; false at the end.
    bool next(OutputItem& item);
    /// The tiles' reports (in group order), available from construction.
    const std::vector<TileReport>& tiles() const;
    const OutputCounts& counts() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// The largest number of result files merged at once (more are merged in rounds first).
inline constexpr std::size_t k_merge_fan_in = 128;

} // namespace trisnap::stitch
