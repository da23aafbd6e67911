#pragma once
// What a finished tile leaves in the work directory for the stitch (result-<group>, in input
// order, and seams-<group>), and their encodings.
//  - A Piece is what one tile says about one feature: its whole output (the tile owns every edge
//    of it and had it whole), or the edges it owns (an edge belongs to the tile whose core holds
//    its midpoint), the largest move it measured in its core, and the problems whose evidence
//    lies in its core (105, 205, 207, 209; the rest is judged on the stitched feature), and what
//    it saw of the boundaries the feature shares with others (evidence for 210).
//  - A SeamEdge is an edge the tile produced within the seam band of another leaf's core, with
//    the leaves it is near and whether the tile owns it: what the seam check compares.
#include "core/assemble.hpp"
#include "core/problems.hpp"
#include "core/snap.hpp"
#include "tiling/binary_io.hpp"
#include "tiling/plan.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace trisnap::stitch {

struct Piece {
    std::uint64_t rank = 0; ///< the feature's rank in features.bin
    double displacement = 0;
    bool whole = false;
    bool has_z = false;
    /// When whole: the feature's output. Otherwise its finished polygons: those inside the core
    /// of one of the tile's leaves, all of whose edges the tile owns (stitched without tracing
    /// them again unless another edge meets them).
    Geometry geometry;
    std::vector<DirectedEdge> edges; ///< when not whole: the other edges the tile owns
    std::vector<Problem> problems;   ///< feature_id: the engine id
    /// What the tile saw of the boundaries the feature shares (FeatureOutput::shared; other:
    /// the engine id); the stitch merges its tiles' and judges problem 210.
    std::vector<SharedBoundary> shared;
};

struct SeamEdge {
    std::uint64_t rank = 0;
    DirectedEdge edge;
    bool owned = false;
    std::vector<std::uint32_t> near; ///< leaves whose core lies within the seam band, ascending
};

/// One executed tile (a group of one or more plan leaves), for the report.
struct TileReport {
    std::size_t id = 0;              ///< smallest plan leaf in it
    std::size_t leaves = 1;          ///< plan leaves merged into it
    tiling::Box core;                ///< finite box of its core(s)
    double halo = 0;                 ///< final halo width (layer units)
    int growths = 0;                 ///< halo doublings (cascades reaching the core)
    bool cascade_unbounded = false;  ///< still reaching the core at the last growth
    double cascade_x = 0;            ///< where a cascade reached the core (first growth)
    double cascade_y = 0;
    std::uint64_t cascade_rank = 0;   ///< a feature the cascade moved (its rank)
    std::size_t features = 0;        ///< features given to it (whole or cut)
    std::size_t input_vertices = 0;
    std::size_t output_edges_owned = 0;
    std::size_t problems = 0;        ///< problems it reported in its core
    double seconds = 0;              ///< wall time of its run
    std::size_t runs = 1;            ///< times its leaves were snapped (seam merges run again)
    SnapStats stats;                 ///< the engine's counters for this tile
    /// The tile failed alone and merged with its neighbours (--on-error skip): its result holds
    /// one piece per feature of its input, each with problem 303 and no geometry, and no seams.
    bool failed = false;
    std::string failure;             ///< the engine's message, when failed
};

void put_piece(tiling::ByteWriter& w, const Piece& p);
Piece get_piece(tiling::ByteReader& r);
void put_seam_edge(tiling::ByteWriter& w, const SeamEdge& e);
SeamEdge get_seam_edge(tiling::ByteReader& r);
void put_tile_report(tiling::ByteWriter& w, const TileReport& t);
TileReport get_tile_report(tiling::ByteReader& r);
/// The seam rounds' notes (301 with the rank of its feature), as one work file's bytes.
std::string encode_notes(const std::vector<std::pair<std::uint64_t, Problem>>& notes);
std::vector<std::pair<std::uint64_t, Problem>> decode_notes(const std::string& bytes);

/// Exact identity of a seam edge: feature, coordinates and the bits of z.
bool seam_less(const SeamEdge& a, const SeamEdge& b);
bool seam_equal(const SeamEdge& a, const SeamEdge& b);

} // namespace trisnap::stitch
