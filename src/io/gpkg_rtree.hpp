#pragma once
// A GeoPackage layer's spatial index, bulk loaded. GDAL 3.6 fills a new layer's R-tree at the
// end with one SQLite R*-tree insertion per feature (about 10 us each here: 2.6 of ogr2ogr's 3.8
// CPU seconds on 247,551 polygons, 2 of trisnap's 14 on the same layer). The writer creates the
// layer without GDAL's index (SPATIAL_INDEX=NO), keeps each written feature's box, and at the end
// writes the index itself: the boxes packed into full nodes by Sort-Tile-Recursive (Leutenegger,
// Lopez, Edgington 1997), the nodes written straight into SQLite's R-tree tables, then the six
// triggers and the gpkg_extensions row of the GeoPackage R-tree extension (spec 1.2, F.3), as
// GDAL would have written them. What a reader gets is the same extension, the same boxes (32-bit
// floats rounded outwards, as SQLite rounds them), another node layout. SQLite's rtreecheck()
// passes on it (tests/unit/io), and later edits through GDAL keep it in step (the triggers).
//
// The node format is SQLite's (ext/rtree/rtree.c, "node format"): every node is a blob of the
// root's size; two bytes of tree depth (root only), two bytes of cell count, then per cell a
// 64-bit id (a feature's FID in a leaf, a child's node number above) and minx, maxx, miny, maxy
// as 32-bit floats, all big-endian. The root is node 1; <rtree>_rowid maps each FID to its leaf,
// <rtree>_parent each node but the root to its parent.
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace trisnap {

/// One feature's box as the index stores it: 32-bit floats, min rounded down and max up.
struct RtreeEntry {
    std::int64_t id = 0;
    float min_x = 0, max_x = 0, min_y = 0, max_y = 0;
};

/// The box of `id` with every side rounded outwards to a float (the box contains the exact one).
RtreeEntry rtree_entry(std::int64_t id, const OGREnvelope& box);

/// A packed tree. nodes[k] is node number k + 1 (nodes[0] is the root); a leaf's cells hold
/// FIDs, an inner node's its children's node numbers. parent[k] is the parent's number (0 for
/// the root). depth is the root's distance from the leaves (0: the root is the only node).
struct PackedRtree {
    std::vector<std::vector<RtreeEntry>> nodes;
    std::vector<std::int64_t> parent;
    int depth = 0;
    std::size_t first_leaf = 0; ///< nodes[first_leaf..] are the leaves (numbered from the root down)
};

/// Sort-Tile-Recursive packing of `entries` into nodes of at most `max_cells` cells (>= 2): per
/// level, ceil(sqrt(P)) vertical slices of the centres sorted by x, each sorted by y and cut
/// into full nodes. Deterministic: ties go by centre then id. No entries: one empty root.
PackedRtree pack_rtree(std::vector<RtreeEntry> entries, std::size_t max_cells);

/// One node as SQLite stores it: `node_size` bytes; `depth` is written for the root only.
std::string rtree_node_blob(const std::vector<RtreeEntry>& cells, int depth, bool root, std::size_t node_size);

/// Collects the boxes of the features written to one new GeoPackage layer, then writes its
/// index. Up to `max_entries` boxes are kept in memory and packed there. Above that, with a
/// scratch directory, the boxes go to sorted runs on disk and the same tree is packed level by
/// level from their merge (each level's nodes, the parent and rowid rows spilled and sorted the
/// same way): the index's rows are the ones the in-memory packing writes, in the same order, so
/// OUT has the same bytes under any --memory-limit. Memory stays within about twice the box
/// budget. Without a scratch directory, above the budget write() asks GDAL to build the index
/// (its CreateSpatialIndex(), the slower insertion path: ~6 us a feature here, measured on 1 M
/// and 435 k features).
class GpkgIndexBuilder {
public:
    /// `scratch`: where the runs go (created when needed; empty: none); `path`: OUT, for errors.
    explicit GpkgIndexBuilder(std::size_t max_entries, std::filesystem::path scratch = {}, std::string path = {});
    ~GpkgIndexBuilder();
    GpkgIndexBuilder(const GpkgIndexBuilder&) = delete;
    GpkgIndexBuilder& operator=(const GpkgIndexBuilder&) = delete;

    /// Room for `features` boxes (at most the box budget), kept at once.
    void reserve(std::size_t features) { m_entries.reserve(std::min(features, m_max_entries)); }

    /// A feature written with this FID and geometry (null and empty geometries are not indexed,
    /// as in GDAL's triggers).
    void add(std::int64_t fid, const OGRGeometry* geometry);
    /// A feature written with this FID whose non-empty geometry has this box. Throws io_error
    /// naming OUT when a run cannot be written to the scratch directory (a full disk).
    void add(std::int64_t fid, const OGREnvelope& box);

    /// Creates the index of `layer` (a table in `dataset`, inside its open transaction): the
    /// R-tree table filled (its rows bound to statements prepared once on GDAL's own SQLite
    /// connection), its triggers, the extension row. Where the dataset does not hand out its
    /// connection, GDAL builds the index (as above the box budget without a scratch directory).
    /// Throws io_error naming `path`, its message ending with `outcome` (what was left at OUT).
    void write(GDALDataset& dataset, OGRLayer& layer, const std::string& path, const std::string& outcome);

private:
    struct Spill;
    std::size_t m_max_entries;
    std::filesystem::path m_scratch;
    std::string m_path;
    std::vector<RtreeEntry> m_entries;
    std::unique_ptr<Spill> m_spill;
    bool m_fallback = false;
};

} // namespace trisnap
