#pragma once
// The first two steps of a tiled run, each one streaming pass with bounded memory:
//  1. FeatureSpool: every input feature, in input order, cleaned (1xx problems reported) and
//     written once to features.bin, with a bounded order-independent sample of its vertices
//     for the plan, the layer's extent, and whether the FIDs can serve as engine ids;
//  2. make_buckets(): the tile plan from that sample, each leaf's reach box R (a pass that grows
//     R for the long edges meeting core + halo), and each leaf's bucket (a pass that writes
//     every feature meeting R, cut to R, into it). A leaf whose bucket holds more vertices than
//     a tile may is split in two, again and again, from its own bucket.
// Nothing here holds the layer: memory is the sample, the per-leaf tables and bucket buffers.
#include "core/geometry.hpp"
#include "core/input_cleaning.hpp"
#include "core/problems.hpp"
#include "stitch/layout.hpp"
#include "tiling/records.hpp"
#include "tiling/sample.hpp"
#include "tiling/work_store.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace trisnap::stitch {

/// What the read pass learned about the layer (kept in the work directory as spool.meta).
struct SpoolMeta {
    std::uint64_t records = 0;  ///< input features read, snapped or not
    std::uint64_t spooled = 0;  ///< features in features.bin (given to the engine)
    std::uint64_t vertices = 0; ///< their engine vertices
    bool fids_unique = true;    ///< engine ids are the FIDs; else their input positions
    tiling::PlanInput sample;
    std::uint64_t largest_vertices = 0; ///< the largest feature's engine vertices
    std::int64_t largest_fid = 0;
    /// Without `sample`, the sample's vertices are left out (its extent and counts stay): what
    /// is loaded back then cannot be planned from.
    void save(tiling::ByteWriter& w, bool with_sample = true) const;
    static SpoolMeta load(tiling::ByteReader& r);
};

/// A stretch of the input read on a thread of its own (app/read_phase.cpp): the same work per
/// feature as FeatureSpool::add()/skip(), to be appended with FeatureSpool::append() after every
/// feature before it. In memory it holds its features' records (their cleaned vertices) until
/// then; spilled (out of core) they and the FIDs go to files of the store as they come, and the
/// part holds only its sample and the files' buffers.
class SpoolPart {
public:
    /// In memory. `block_bytes`: the size of the blocks its records are kept in (a record larger
    /// than that gets a block of its own).
    SpoolPart(double tolerance, std::size_t sample_cap, std::size_t block_bytes = std::size_t{4} << 20);
    /// Spilled: the records go to `store`'s file `prefix` + "features" (framed as features.bin
    /// frames them) and every FID to `prefix` + "fids"; seal() commits them.
    SpoolPart(double tolerance, std::size_t sample_cap, tiling::WorkStore& store, const std::string& prefix);
    SpoolPart(SpoolPart&&) noexcept;
    SpoolPart& operator=(SpoolPart&&) noexcept;
    ~SpoolPart();
    /// FeatureSpool::add(); `seq` is the feature's position in the whole input.
    void add(std::uint64_t seq, std::int64_t fid, const Geometry& geometry, std::vector<Problem>& problems);
    /// FeatureSpool::skip().
    void skip(std::int64_t fid);
    /// After the last add() or skip() of a spilled part: its files committed (on the thread
    /// that wrote them), ready for append(). Nothing for a part in memory.
    void seal();
    /// The blocks its records are held in so far (none when spilled).
    std::size_t blocks() const { return m_blocks.size(); }
    bool spilled() const { return m_spill != nullptr; }

private:
    friend class FeatureSpool;
    struct Spill;
    double m_tolerance;
    tiling::VertexSample m_sample;
    SpoolMeta m_meta;                  ///< records, spooled, vertices, the largest feature
    std::vector<std::int64_t> m_fids;  ///< every feature's, spooled or not, in order
    std::size_t m_block_bytes;
    /// The spooled features' records framed as the features file frames them (RecordWriter: a
    /// 32-bit length, then the record), one after the other in blocks of about m_block_bytes (a
    /// block never grows by copying what it holds; a record never spans two). Appending hands
    /// the blocks to the file whole (OutFile::write_block): in memory, without a copy.
    std::vector<std::string> m_blocks;
    std::vector<std::uint64_t> m_starts; ///< each record's offset in the blocks' concatenation
    std::uint64_t m_bytes = 0;           ///< the blocks' bytes
    std::string m_record;
    std::unique_ptr<Spill> m_spill;      ///< the files of a spilled part; null in memory
};

class FeatureSpool {
public:
    /// `sample_cap`: vertices kept for the plan; `fid_buffer`: FIDs sorted in memory at once.
    FeatureSpool(tiling::WorkStore& store, double tolerance, std::size_t sample_cap, std::size_t fid_buffer);
    ~FeatureSpool();
    /// Cleans and spools one feature to snap; its repairs go to `problems` carrying `fid`.
    /// Call in input order; `seq` is the input position.
    void add(std::uint64_t seq, std::int64_t fid, const Geometry& geometry, std::vector<Problem>& problems);
    /// A feature read but not snapped (passed through or rejected): its FID still counts.
    void skip(std::int64_t fid);
    /// The features of `part`, as if each had been added or skipped here now, in its order:
    /// the same files, meta and sample as that sequence of calls gives. A spilled part must be
    /// sealed; its files are read back and removed.
    void append(SpoolPart&& part);
    /// Several layers in one run: call after each layer's features. True when that layer's FIDs
    /// were unique within it (its output can keep them); the engine then takes input positions
    /// as ids whatever the answer, since FIDs may repeat across layers (meta.fids_unique false).
    bool end_layer();
    /// Commits features.bin, features.idx and spool.meta. Without end_layer(), one layer:
    /// meta.fids_unique says whether its FIDs serve as engine ids. spool.meta holds the plan's
    /// sample only in a store on disk, the one a resumed run or another process reads it from;
    /// a store in memory ends with the process, and the caller has the returned meta.
    SpoolMeta finish();

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// The engine id of a spooled feature.
inline std::int64_t engine_id(const SpoolMeta& meta, const detail::CleanFeature& f)
{
    return meta.fids_unique ? f.id : static_cast<std::int64_t>(f.index);
}

/// Reads features.bin in order, or one feature by its position in it.
class SpooledFeatures {
public:
    /// `outline`: features come as tiling::get_clean_feature's outlines (the stitch needs only
    /// their counts, flags and first points); they are read from features.outline when the spool
    /// was cut to it (cut_spool_to_outlines()).
    explicit SpooledFeatures(const tiling::WorkStore& store, bool outline = false);
    /// The features whose records are features.bin's bytes [begin, end) (record boundaries, as
    /// features.idx gives them), in order.
    SpooledFeatures(const tiling::WorkStore& store, std::uint64_t begin, std::uint64_t end);
    /// The next feature in input order; false at the end.
    bool next(detail::CleanFeature& f, bool& has_z);

private:
    std::unique_ptr<tiling::InFile> m_file;
    tiling::RecordReader m_reader;
    std::string m_record;
    bool m_outline;
};

/// Random access to spooled features by their rank in features.bin.
class FeatureLookup {
public:
    explicit FeatureLookup(const tiling::WorkStore& store);
    detail::CleanFeature at(std::uint64_t rank, bool& has_z);
    std::uint64_t size() const { return m_count; }

private:
    std::unique_ptr<tiling::InFile> m_features;
    std::unique_ptr<tiling::InFile> m_offsets;
    tiling::RecordReader m_reader;
    std::uint64_t m_count = 0;
};

struct BucketOptions {
    double halo = 0;                        ///< layer units
    double seam_band = 0;                   ///< layer units
    std::uint64_t max_tile_vertices = 0;    ///< 0: no limit; larger buckets are split
    std::size_t buffer_bytes = 64u << 20;   ///< bucket data buffered before appending (all threads together)
    int threads = 1;                        ///< 2 or more: the passes over the features run in two parts at once,
    std::uint64_t least_part_bytes = 8u << 20; ///< where each part holds at least this much of features.bin
};

/// A tile that cannot be made small enough for the budget: what() says which and how much;
/// vertices() is what it needs in one triangulation.
class budget_error : public std::runtime_error {
public:
    budget_error(const std::string& what, std::uint64_t vertices) : std::runtime_error(what), m_vertices(vertices) {}
    std::uint64_t vertices() const { return m_vertices; }

private:
    std::uint64_t m_vertices;
};

/// Called with (features done, features in total) during each pass.
using PassProgress = std::function<void(std::uint64_t, std::uint64_t)>;

/// Plans from `sample` (meta.sample's vertices, taken out of it: the plan is their only reader),
/// computes reach boxes and fills the buckets; commits layout.bin.
TileLayout make_buckets(tiling::WorkStore& store, const SpoolMeta& meta, tiling::PlanInput sample,
                        const TilingOptions& tiling, const BucketOptions& options, const PassProgress& progress = {});

/// A leaf's bucket, in input order: every spooled feature meeting its reach, cut to it.
/// A plan of one leaf keeps no bucket file (whole_spool_bucket()): that bucket is made here from
/// features.bin, each feature cut as make_buckets() cuts them (a layer then is not stored twice).
std::vector<tiling::TileFeature> read_bucket(const tiling::WorkStore& store, const TileLayout& layout, const SpoolMeta& meta,
                                             std::size_t leaf);
/// True when the layout's buckets are made from features.bin as they are read (a plan of one leaf).
bool whole_spool_bucket(const TileLayout& layout);

/// Replaces features.bin and features.idx by features.outline: each feature as an outline (what
/// SpooledFeatures reads with `outline`). For a plan of one leaf in memory once its tile has its
/// bucket, when nothing will read the features whole again (no retry, no halo growth): the
/// engine holds them from there on, and the layer is not held twice (on Andorra x43 --no-tiles,
/// features.bin is 40 MB of the run's peak). Does nothing when the spool was cut already.
void cut_spool_to_outlines(tiling::WorkStore& store);
/// Whether the spool was cut to outlines: full features can no longer be read.
bool spool_cut_to_outlines(const tiling::WorkStore& store);

/// Grows `reach` (starting as r0) by both ends of every edge of the feature that meets r0.
void grow_reach(const detail::CleanFeature& cf, const tiling::Box& feature_box, const tiling::Box& r0, tiling::Box& reach);
tiling::Box box_of(const detail::CleanFeature& cf);

/// A tile's box R: core + halo, grown to hold both ends of every edge of `from` meeting that
/// (a long edge moves with its far end), + halo. `from` must hold every input edge meeting
/// core + halo whole (a bucket of a leaf whose box holds that does).
tiling::Box reach_box(const tiling::Box& core, double halo, const std::vector<tiling::TileFeature>& from);

/// The feature as the engine's own rings/lines (open rings), for cutting it again.
detail::CleanFeature as_clean(const Feature& f);

} // namespace trisnap::stitch
