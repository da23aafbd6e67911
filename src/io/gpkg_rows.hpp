#pragma once
// A new GeoPackage layer's rows, inserted through GDAL's own SQLite connection (the one its
// driver hands out as "SQLITE_HANDLE") with each geometry's blob encoded straight from the
// engine's result. Through GDAL (OGRGeoPackageTableLayer::ICreateFeature) a snapped feature was
// made into OGR objects (rings, an output OGRFeature filled from the input's), encoded from them
// and bound; that per-feature path was ~0.8 s of Andorra x43's 1.2 s write phase, SQLite's own
// insertion 0.22-0.26 s (bench/results/REPORT.md, "What still caps two threads"), and it ran on
// the one writing thread. Here the blob is made on the write phase's reading side
// (app/write_phase.cpp) and the writing thread only binds and steps, sixteen rows to a
// statement (GpkgRows::k_batch).
//
// The rows are GDAL's: the same values bound to the same columns (FID, geometry, then the
// fields in the layer's order, unset and null fields as NULL, integers as 64-bit integers, reals
// as doubles, strings as their text) and the same blob bytes (GPkgGeometryFromOGR: "GP", version
// 0, a flags byte with the host's byte order, an XY or XYZ envelope (none for points and empty
// geometries, which set the empty bit), the srs_id, then ISO WKB). After the last row the
// layer's extent goes into gpkg_contents and its feature count into gpkg_ogr_contents, as GDAL
// would set them. A file of one layer written so differs from one written through GDAL only in
// the two counters of SQLite's file header that count write transactions (offsets 24 and 92;
// tests/unit/io compares the rest byte for byte). With several layers in one file the tables are
// created up front (GDAL creates each at its first feature), so the pages are laid out
// otherwise; the rows, extents and counts are GDAL's (tested). For the same reason a layer's
// queued rows need not go in before another layer's features: each table gets its own rows in
// their order whenever its queue is flushed.
//
// Only where that holds does a layer take rows (GpkgRows::open): a new table of a declared
// geometry type (not Unknown: GDAL then edits gpkg_geometry_columns per feature), no field
// with a default value (GDAL fills unset fields with it), fields of type Integer, Integer64,
// Real or String with the input's type (so FieldFidelity has nothing to find), none named like
// the FID column, no TRUNCATE_FIELDS. A geometry GDAL registers an extension for (curves,
// surfaces, TINs) goes through GDAL; its box still counts in the extent written here.
#include "core/geometry.hpp"
#include "io/gpkg_rtree.hpp"

#include <ogrsf_frmts.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace trisnap {

/// Turns off SQLite's process-wide memory statistics (SQLITE_CONFIG_MEMSTATUS), which take one
/// mutex on every SQLite allocation and free, shared by every connection (most of the 7 % the
/// write phase's writing thread spent in pthread_mutex_lock on Jakarta, perf). Off: the writer
/// alone 2-4 % faster (bench_write's rows, 3 rounds of 5); end to end within the noise (Jakarta
/// at 2 threads, write phase medians 0.24 -> 0.20 s over 8 interleaved pairs, 0.23 both over 6
/// more). Nothing in trisnap or GDAL reads those statistics (libgdal imports neither
/// sqlite3_memory_used nor sqlite3_status). Only before
/// SQLite's first use (main() calls it first thing); false when it is too late.
bool sqlite_without_memory_statistics();

/// A geometry as a GeoPackage blob, with what the layer's extent and index need of it.
struct GpkgGeometry {
    std::string blob;    ///< empty: a null geometry
    OGREnvelope box;     ///< set when `boxed`
    bool boxed = false;  ///< not null, not empty: counts in the extent and the spatial index
};

/// A row's field values, taken from the input feature where it was read (GpkgRows::take): the
/// writing thread then binds them without touching the feature. Read there, the feature's
/// fields and its definition (whose reference count the reading thread changes with every
/// feature) went back and forth between the cores: 11 % of the writing thread's samples in
/// OGRFeature::IsFieldSetAndNotNull, 6 % of the reading thread's in CPLAtomicAdd (Andorra x43,
/// 2 threads, perf).
struct GpkgValues {
    enum class Kind : unsigned char { null, integer, real, text };
    struct Value {
        Kind kind = Kind::null;
        std::int64_t integer = 0;
        double real = 0;
        std::uint32_t at = 0, size = 0; ///< a text's bytes in `texts`
    };
    std::vector<Value> values; ///< one per output field, in the layer's order
    std::string texts;         ///< the texts, one after the other
    std::int64_t fid = 0;      ///< the input feature's FID
};

/// The blob GDAL would write for to_ogr(geometry, like) (io/ogr_geometry.hpp): the same bytes,
/// without the OGR objects. An empty `geometry` gives a null one.
void encode_gpkg(const Geometry& geometry, OGRwkbGeometryType like, std::int32_t srs_id, GpkgGeometry& out);

/// The blob GDAL would write for `geometry` (null: a null one). False, `out` untouched, for a
/// geometry GDAL registers a GeoPackage extension for (a curve, surface, polyhedral surface, TIN
/// or triangle, also inside a collection): that feature goes through GDAL.
bool encode_gpkg(const OGRGeometry* geometry, std::int32_t srs_id, GpkgGeometry& out);

/// The rows of one new GeoPackage layer. Not thread-safe: the writing thread's.
class GpkgRows {
public:
    /// Rows for `layer` (just created in `dataset`, a GeoPackage), whose field i holds input
    /// field `source_of[i]` of `input` (-1: the original FID, for `orig_fid`); `keeps_fids`:
    /// rows take the input FID. Null when the layer cannot take rows (see above) or the dataset
    /// does not hand out its connection. Throws io_error naming `path` when SQLite refuses the
    /// statement.
    /// `index`, when given, gets every inserted row's FID and box.
    static std::unique_ptr<GpkgRows> open(GDALDataset& dataset, OGRLayer& layer, const OGRFeatureDefn& input,
                                          const std::vector<int>& source_of, bool keeps_fids,
                                          const std::vector<std::string>& layer_options, const std::string& path,
                                          GpkgIndexBuilder* index);
    ~GpkgRows();
    GpkgRows(const GpkgRows&) = delete;
    GpkgRows& operator=(const GpkgRows&) = delete;

    /// The layer's srs_id, for the blobs' headers.
    std::int32_t srs_id() const { return m_srs_id; }

    /// The values of input feature `source` (FID `fid`) for this layer's fields: GDAL's binding
    /// (unset and null fields NULL, integers 64-bit, reals doubles, strings their text; the
    /// original FID for orig_fid). Reads only what open() set: callable on any thread.
    void take(const OGRFeature& source, std::int64_t fid, GpkgValues& out) const;

    /// Rows go in k_batch to a statement: SQLite's AUTOINCREMENT reads and writes back the
    /// table's sqlite_sequence row once per statement, not per row (54,432 Jakarta-like rows in
    /// one transaction: 140 ms one to a statement, 84 ms sixteen; 74 and 65 ms without
    /// AUTOINCREMENT). A batch SQLite refuses (a constraint) is undone by SQLite and its rows go
    /// in one at a time, so only the refused ones are left out. Batches weigh at most
    /// k_batch_bytes (a statement's journal stays in memory); once the queue weighs more, its
    /// rows go in one by one (the queue holds at most that and one row).
    static constexpr std::size_t k_batch = 16;
    static constexpr std::size_t k_batch_bytes = std::size_t{1} << 15;

    /// A row SQLite refused: the input FID and why (a constraint: problem 902, in GDAL's words).
    struct Refusal {
        std::int64_t fid = 0;
        std::string message;
    };

    /// Queues a row of `values` (take()) with `geometry` (both copied): it goes in with its
    /// batch, here or at flush(). A refusal is kept for take_refusals(). Throws io_error when
    /// SQLite fails otherwise (the disk).
    void insert(const GpkgValues& values, const GpkgGeometry& geometry);
    /// Inserts the queued rows (before a feature goes through GDAL, so rows keep input order,
    /// and after the last). Throws io_error as insert().
    void flush();
    /// The refusals found since the last call, in input order.
    std::vector<Refusal> take_refusals() { return std::exchange(m_refusals, {}); }
    /// Rows inserted so far (refused ones not counted, queued ones not yet).
    std::size_t inserted() const { return m_inserted; }

    /// A feature written through GDAL into this layer (its geometry left to GDAL): its box.
    void include(const OGRGeometry* geometry);

    /// After the last feature and flush() (`features` written in all, rows and GDAL's): GDAL's
    /// pending metadata first (SyncToDisk), then the extent and the feature count. Throws io_error.
    void finish(std::size_t features);

private:
    /// A queued row: its blob and values in m_bytes and m_values.
    struct Queued {
        std::int64_t fid = 0;
        std::size_t blob_at = 0, blob_size = 0; ///< in m_bytes; size 0: a null geometry
        std::size_t values_at = 0;              ///< in m_values, m_source_of.size() of them
        OGREnvelope box;
        bool boxed = false;
    };

    GpkgRows(OGRLayer& layer, sqlite3* db, std::vector<int> source_of, bool keeps_fids,
             const std::string& path, GpkgIndexBuilder* index);
    sqlite3_stmt* prepare(std::size_t rows) const;
    int bind(sqlite3_stmt* statement, int at, const Queued& row) const;
    void run_batch();
    void run_one(const Queued& row);
    void inserted(const Queued& row, std::int64_t rowid);
    void include(const OGREnvelope& box);
    [[noreturn]] void fail(const std::string& what) const;
    void run(const std::string& sql) const;

    OGRLayer& m_layer;
    sqlite3* m_db;
    sqlite3_stmt* m_insert = nullptr; ///< one row
    sqlite3_stmt* m_batch = nullptr;  ///< k_batch rows
    GpkgIndexBuilder* m_index;
    std::vector<Queued> m_queue;
    std::string m_bytes;                    ///< the queued rows' blobs and texts
    std::vector<GpkgValues::Value> m_values; ///< the queued rows' values (texts' `at` in m_bytes)
    std::vector<Refusal> m_refusals;
    std::size_t m_inserted = 0;
    std::vector<int> m_source_of;
    std::vector<bool> m_text; ///< per field: bound as text (else as a number)
    std::vector<bool> m_real; ///< per field: bound as a double
    bool m_keeps_fids;
    std::string m_path;
    std::int32_t m_srs_id = 0;
    OGREnvelope m_extent;
    bool m_has_extent = false;
};

} // namespace trisnap
