#pragma once
// The shape of a tiled run, as kept in its work directory so that any phase (and any machine
// of a cluster job) can pick it up: the tile plan, what each plan leaf sees (its reach box R and
// the size of its bucket), and the current tiles ("groups": one leaf each at first; merged when
// their seams disagree). Names of the work files live here too.
#include "core/snap.hpp"
#include "tiling/binary_io.hpp"
#include "tiling/plan.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace trisnap::stitch {

/// How to cut the layer into tiles; every field says what changes when you flip it.
/// What a tile does when the engine throws inside it (a CGAL precondition, a logic_error): stop
/// the run (tile_error), or retry it merged with its neighbours and, when that fails too, drop
/// the features it met with problem 303 and go on (`--on-error skip`). Running out of memory
/// and a cancel are never caught.
enum class OnError { stop, skip };

struct TilingOptions {
    tiling::PlanOptions plan;
    /// Halo width as a factor of t. Cascades of snaps were seen to reach 9t (Monaco, 1e-6 deg)
    /// and 16t (1e-5 deg); a cascade that reaches the core from the halo's border doubles it.
    double halo_factor = 32;
    /// How many times a tile's halo may double when the cascade test fires (0: no test). The
    /// test is conservative (any chain of moved vertices within 2t links the halo's border to
    /// the core): it fired on 2 of Monaco's 4 tiles at 1e-6 deg and doubled their cost, while
    /// tiled output without it was 100 % identical to untiled on every layer measured (halo 4t
    /// to 32t). So it is off by default; the seam check keeps the layer consistent either way.
    int max_growth = 0;
    /// Threads for tiles (0: all cores). The output does not depend on it.
    int threads = 0;
    OnError on_error = OnError::stop;
};

/// The encoding of the work files (tiling/records.hpp, stitch/tile_result.hpp), in the run's
/// manifest: raised whenever a record changes, so that a directory another encoding wrote is
/// refused by --resume instead of misread. 2: the tile report keeps every engine counter;
/// records.bin flags the features the read reported a problem for; read.bin lists the problem
/// log's runs instead of holding the problems. 3: a piece that is not whole carries its
/// finished polygons after its edges. 4: read.bin leaves the spool's meta to spool.meta. 5: a plan of
/// one leaf writes no bucket file (its bucket is features.bin). 6: a piece carries its shared-boundary
/// evidence. 7: a bucket may go on in a second file (files::bucket_tail), the spool's second thread's.
inline constexpr int k_work_format = 7;

/// Work file names.
namespace files {
inline const std::string features = "features.bin";  ///< cleaned features, input order
inline const std::string offsets = "features.idx";   ///< u64 offset of each, in order
/// features.bin's outlines, in its stead once a plan of one leaf has its bucket (in memory only)
inline const std::string outlines = "features.outline";
inline const std::string spool_meta = "spool.meta";  ///< extent, sample, counts, FID check
inline const std::string layout = "layout.bin";      ///< TileLayout
inline const std::string groups = "groups.bin";      ///< Groups
inline std::string bucket(std::size_t leaf) { return "bucket-" + std::to_string(leaf); }
/// The rest of a leaf's bucket, after bucket(leaf)'s records: the features of the spool's second
/// part (stitch/buckets.cpp), filled at the same time as bucket(leaf) by another thread.
inline std::string bucket_tail(std::size_t leaf) { return "bucket-" + std::to_string(leaf) + ".tail"; }
inline std::string result(std::size_t group) { return "result-" + std::to_string(group); }
inline std::string seams(std::size_t group) { return "seams-" + std::to_string(group); }
} // namespace files

/// The plan and what every leaf sees.
struct TileLayout {
    tiling::TilePlan plan;
    std::vector<tiling::Box> reach;             ///< per leaf: R (core + halo, grown for long edges)
    std::vector<std::uint64_t> bucket_vertices; ///< per leaf: engine vertices in its bucket
    std::vector<std::uint64_t> bucket_features; ///< per leaf: features in its bucket
    double halo = 0;                            ///< layer units
    double seam_band = 0;                       ///< edges this close to another tile are on a seam

    /// The finite box of a leaf's core (clipped to the data extent).
    tiling::Box core_box(std::size_t leaf) const { return tiling::clip(plan.core(leaf), plan.extent()); }
    bool has_data(std::size_t leaf) const { return !core_box(leaf).empty(); }
    void save(tiling::ByteWriter& w) const;
    static TileLayout load(tiling::ByteReader& r);
};

/// The current tiles: each a set of plan leaves. Ids of merged groups are new (appended).
struct Groups {
    std::vector<std::size_t> of_leaf;             ///< group id per plan leaf
    std::vector<std::vector<std::size_t>> leaves; ///< leaves per group id (empty: merged away)
    std::vector<double> halo;                     ///< per group: the halo it starts from
    std::vector<std::uint32_t> runs;              ///< per group: how often its leaves were snapped
    std::size_t seam_merges = 0;

    /// One group per leaf.
    static Groups of_layout(const TileLayout& layout);
    /// Groups that hold a leaf whose bucket has features (the tiles that run), ascending.
    std::vector<std::size_t> live(const TileLayout& layout) const;
    void save(tiling::ByteWriter& w) const;
    static Groups load(tiling::ByteReader& r);
};

/// The finite box of a group's cores, and its report region (the union of its cores).
tiling::Box group_core(const TileLayout& layout, const Groups& groups, std::size_t group);
Region group_region(const TileLayout& layout, const Groups& groups, std::size_t group);

} // namespace trisnap::stitch
