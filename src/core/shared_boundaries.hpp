#pragma once
// Problem 210 (shared_boundary_lost): two polygons that shared a boundary before snapping share
// none after it, both still written. Snapping can merge every vertex of a short chain into one
// point: on Monaco at 5 m, six vertices 2-3 m apart zigzag along the 9.7 m wall two buildings
// share; closest pairs first, each merge lands within t of the next vertex, and the whole wall
// became one point. The two buildings then meet at that point only. The promise "shared
// boundaries stay shared" is broken there, so the run says so, on the later of the two features
// in input order, naming the other (the independent checker, `trisnap assess`, found it as an
// unexplained gap).
//
// The evidence is read from the owner table twice, before and after snapping. A piece of input
// edge bounds a polygon when the polygon owns it an odd number of times (labels are crossing
// parities: labelling.cpp), so "A and B share a boundary" is "some constrained edge is owned an
// odd number of times by both". Each reading counts only inside the run's report region, so the
// tiles of a tiled run can each say what they saw of a pair and the stitch can merge it:
//  - before: an input piece bounding both that meets the closed region (every point of the plane
//    lies in some tile's core, and the input edges through a point of a core are all in that
//    tile, whole: the union over tiles is exactly the pairs an untiled run finds; the smallest
//    point of those pieces is where the problem is placed, the same in both);
//  - after: an output edge bounding both whose midpoint lies in the region (the stitched output
//    is the union of the edges whose midpoint lies in the tile's core);
//  - length: the pieces' lengths inside the region (half-open: a point belongs to one tile) add up to
//    the shared length, and a boundary shorter than t is not reported: its ends are closer
//    than t, so snapping must merge them (the sums are in different orders tiled and untiled:
//    a wall within a few ulps of t long could be judged differently);
// A pair is lost when it is before somewhere, after nowhere, shared over at least t, and both
// features are written (a feature that vanished has 201, which says more). The problem goes on
// the later feature of the pair in input order, naming the earlier: a stitch that streams
// features in input order knows then whether both were written (the earlier one's answer is
// kept from its turn), and the pair is accounted for by one problem.
// Edges outside `data_extent` are a tile's detours round its box, not data, and do not count.
// An edge bounding more than k_max_stacked polygons gives no evidence: stacked copies of one
// polygon would make pairs quadratic in the copies (10,000 copies of a square: 5 * 10^7 pairs);
// such layers get no 210 for those edges.
#include "core/input_cleaning.hpp"
#include "core/mesh.hpp"
#include "core/problems.hpp"
#include "core/snap.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace trisnap::detail {

inline constexpr std::size_t k_max_stacked = 8;

class SharedBoundaryEvidence {
public:
    /// `cores`: disjoint boxes making up the region (SnapOptions::report_cores); empty: {region}.
    SharedBoundaryEvidence(const Region& region, const std::vector<Region>& cores, const Region& extent);
    /// Reads the pairs sharing input edge pieces (call before snapping).
    void before(const Mesh& mesh);
    /// Reads the pairs and features bounding output edges (call after snapping).
    void after(const Mesh& mesh);
    /// Per feature (clean index), what was seen of each pair it is in, sorted by the other's id.
    std::vector<std::vector<SharedBoundary>> by_feature(const std::vector<Outline>& clean) const;

private:
    struct Pair {
        bool before = false;
        bool after = false;
        Coord at{};
        double length = 0.0;
    };
    std::vector<Region> m_cores;
    Region m_extent;
    std::unordered_map<std::uint64_t, Pair> m_pairs; ///< key: (a << 32) | b, feature indices a < b
};

/// Merges records that name the same other feature (from several tiles): before and after
/// or-ed, lengths added, the smallest point kept; sorted by other.
void merge_shared_boundaries(std::vector<SharedBoundary>& shared);

/// Whether a merged record is a lost boundary if both features are written: shared before over
/// at least `tolerance` (a shorter one must collapse: its ends are closer than t), not after.
bool lost_candidate(const SharedBoundary& s, double tolerance);

/// Problem 210 for feature `id` at input `position` when it is written and a pair in `shared`
/// (merged) with an earlier feature is lost: a lost_candidate whose other feature is written
/// (`other_written`). One problem naming every such neighbour (the first few by
/// `name(other id)`), at the smallest of their points. True when it added one.
bool report_lost_boundaries(std::int64_t id, std::uint64_t position, bool written, double tolerance,
                            const std::vector<SharedBoundary>& shared,
                            const std::function<bool(const SharedBoundary&)>& other_written,
                            const std::function<std::string(std::int64_t)>& name, std::vector<Problem>& problems);

} // namespace trisnap::detail
