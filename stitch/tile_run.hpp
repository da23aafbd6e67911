#pragma once
// Runs one tile (a group of plan leaves) from the work directory and commits what the stitch
// needs: result-<group> (a TileReport, then one Piece per feature it has something to say
// about, in input order) and seams-<group> (its seam-band edges). Thread-safe: tiles run in
// parallel, each on its own files.
// Input: a single leaf at the base halo reads its own bucket; a merged group, or a tile whose
// halo grew, gathers the features of every leaf near it from features.bin and cuts them to its
// own reach box (rare: seam merges and cascade growths).
#include "stitch/layout.hpp"
#include "stitch/spool.hpp"
#include "stitch/tile_result.hpp"
#include "tiling/tile_job.hpp"

namespace trisnap::stitch {

/// How a tile's features are given to the engine: cut to its reach box (every run), or whole
/// (the last retry of a tile that failed: its region snapped as an untiled run sees it, with no
/// shortcut or detour edge).
enum class TileInputMode { cut, whole };

class TileRunner {
public:
    /// `cut_spool`: once the group's input is gathered, the spool is cut to its outlines
    /// (cut_spool_to_outlines(): for a plan of one leaf in memory that nothing reads whole again).
    TileRunner(tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, const SpoolMeta& meta,
               const SnapOptions& options, int max_growth, bool cut_spool = false);
    /// Snaps the group and commits its files; returns its report. `progress` (optional) is the
    /// engine's callback for this run (SnapProgress: throw from it to stop the tile). `whole`
    /// input with `max_vertices` > 0: throws std::length_error, snapping nothing, when the
    /// features whole hold more vertices than that.
    TileReport run(std::size_t group, const SnapProgress& progress = {}, TileInputMode mode = TileInputMode::cut,
                   std::uint64_t max_vertices = 0) const;
    /// Commits the group as failed (--on-error skip): every feature of its input gets problem
    /// 303, "tile T (N features: FIDs ...) failed <reason>; not written", and no geometry (the
    /// stitch drops it whole), and it has no seams.
    void fail(std::size_t group, const std::string& reason) const;
    /// "312 features: FIDs 12, 15, 17, ... and 304 more" (input FIDs, ascending), for messages.
    std::string describe_features(std::size_t group) const;
    /// Engine vertices the group's input holds (an estimate for a merged group).
    std::uint64_t vertices(std::size_t group) const;

private:
    tiling::TileJobInput gather(std::size_t group, double halo, TileInputMode mode = TileInputMode::cut) const;
    tiling::TileJobInput gather_wide(std::size_t group, double halo, TileInputMode mode) const;
    std::string describe(const std::vector<tiling::TileFeature>& features) const;
    /// "N features: FIDs a, b, ... and M more", the FIDs ascending.
    static std::string describe_fids(std::vector<std::int64_t> fids);
    /// Takes the outcome's geometries.
    void commit(std::size_t group, tiling::TileOutcome& oc, TileReport& report) const;
    void write_files(std::size_t group, const TileReport& report, const std::vector<Piece>& pieces,
                     const std::vector<SeamEdge>& seams) const;

    tiling::WorkStore& m_store;
    const TileLayout& m_layout;
    const Groups& m_groups;
    const SpoolMeta& m_meta;
    const SnapOptions& m_options;
    int m_max_growth;
    bool m_cut_spool;
};

} // namespace trisnap::stitch
