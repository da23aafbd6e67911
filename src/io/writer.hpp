#pragma once
// Writes the snapped layer like ogr2ogr would: same layer name (unless renamed), fields, field
// types and values, CRS and FIDs (or an `orig_fid` field where the format renumbers features).
// A new OUT (or a single-layer one replaced with --overwrite) goes to a temporary directory
// beside the target (".OUT.trisnap-tmp-PID", created before anything else and removed on any
// failure, also when the constructor throws), every write and the final close are checked
// (checked_files.hpp), the files are flushed to disk, and only then renamed into place by
// commit(): a failed or interrupted run, or a full disk, never leaves anything at the target path. An existing multi-layer OUT with --overwrite, --update or
// --append is written in place, in one transaction (io/update_target.hpp).
#include "core/problems.hpp"
#include "io/commit_group.hpp"
#include "io/field_fidelity.hpp"
#include "io/gpkg_rows.hpp"
#include "io/gpkg_rtree.hpp"
#include "io/file_safety.hpp"
#include "io/temp_files.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace trisnap {

struct WriteOptions {
    std::string path;                      ///< the target (OUT)
    std::string format;                    ///< GDAL driver short name; empty = from the extension
    std::string layer_name;                ///< empty = the source layer's name
    std::vector<std::string> layer_options; ///< --lco K=V, passed to CreateLayer
    std::vector<std::string> dataset_options; ///< --dsco K=V, passed to Create
    std::vector<std::string> fields;        ///< --select: the source fields to write; empty = all
    bool overwrite = false;
    bool update = false; ///< --update: write the layer into an existing OUT beside its other layers
    bool append = false; ///< --append: add the features to OUT's layer of that name
    bool renamable = true; ///< -nln could name the output layer (not when several layers go to OUT)
    /// Per source layer: its input FIDs are unusable (duplicate or missing): always add orig_fid.
    /// Missing entries are false.
    std::vector<bool> renumber;
    /// A new GeoPackage layer's spatial index is bulk loaded from the features' boxes, kept in
    /// memory (24 bytes each) up to this many; beyond, they are sorted in runs on disk (OUT's
    /// scratch directory) and the same tree is packed from their merge (io/gpkg_rtree.hpp).
    std::size_t index_boxes = std::size_t{1} << 26;
    /// A new GeoPackage layer takes its features as rows encoded by the caller where it can
    /// (io/gpkg_rows.hpp; rows()); false: every feature through GDAL (tests compare the two).
    bool rows = true;
    ProtectedFiles protected_files; ///< never replaced (the input's files); checked again at the rename
    /// When set, commit() stages OUT's files in this group instead of renaming them, and the
    /// group's owner renames them together with the report (see commit_group.hpp).
    CommitGroup* commit_group = nullptr;
};

/// The driver for `path` (format empty: from the extension, like ogr2ogr). Throws
/// argument_error when the format is unknown, cannot create vector datasets, or is refused for
/// every layer (io/format_limits.hpp: writes no file, no geometry, or quantises coordinates).
GDALDriver& output_driver(const std::string& path, const std::string& format);

/// Refuses an existing target without --overwrite, --update or --append, and a missing parent directory.
void check_output_path(const WriteOptions& options, const std::string& input_path);

/// Refuses an OUT for which `driver` would write any of `options.protected_files` (OUT itself
/// or a companion file such as a Shapefile's .dbf). Throws argument_error naming both.
void check_output_files(const WriteOptions& options, GDALDriver& driver);

/// True when the driver stores the FIDs we set (else the writer adds `orig_fid`).
bool driver_keeps_fids(GDALDriver& driver);

/// Writes one output layer per source layer into one dataset (several layers snapped together go
/// to one OUT, each to a layer of its own name); the checks, the atomic rename and the update
/// transaction cover them all.
class LayerWriter {
public:
    /// Creates the output dataset, layers and fields in the temporary directory: construct it
    /// before the long work so a layer or field the format refuses fails the run at once. Throws
    /// argument_error (format cannot hold the layer's geometry), io_error (creation failed); the
    /// temporary directory is gone either way. Removes stale ".OUT.trisnap-tmp-PID" directories
    /// of processes that no longer exist. Several sources need a driver that holds several
    /// layers (the plan checks it) and no options.layer_name.
    LayerWriter(const WriteOptions& options, const std::vector<OGRLayer*>& sources);
    LayerWriter(const WriteOptions& options, OGRLayer& source) : LayerWriter(options, std::vector<OGRLayer*>{&source}) {}
    ~LayerWriter(); ///< removes the temporary directory unless commit() succeeded
    LayerWriter(const LayerWriter&) = delete;
    LayerWriter& operator=(const LayerWriter&) = delete;

    /// A hint: about `features` features will be written to `layer` (the spatial index keeps
    /// room for their boxes at once instead of growing its list by copies).
    void expect(std::size_t layer, std::size_t features);
    /// Writes the attributes of `source` (by field index) with `geometry` (ownership taken,
    /// may be null). Returns "" on success, else the driver's message (problem 902). Throws
    /// io_error when a write to disk failed (full disk, file size limit): the run cannot go on.
    std::string write(std::size_t layer, const OGRFeature& source, std::int64_t fid, OGRGeometry* geometry);
    /// write() with `geometry` lent, not given: handed back after the write (whatever its
    /// outcome), so that the thread that made it can free it (app/handoff.hpp).
    std::string write_lending(std::size_t layer, const OGRFeature& source, std::int64_t fid,
                              std::unique_ptr<OGRGeometry>& geometry);
    /// The layer's rows when its features can go in as GeoPackage rows whose geometry the
    /// caller encodes (encode_gpkg with rows(layer)->srs_id(), on any thread); null: write().
    const GpkgRows* rows(std::size_t layer) const { return m_targets[layer].rows.get(); }
    /// write() for a layer with rows(): an input feature's values (rows(layer)->take()) with
    /// `geometry`. Rows go in by batches (GpkgRows::k_batch): a row SQLite refuses is reported
    /// by take_refusals() once its batch ran, at the latest after flush_rows() or commit().
    /// Throws io_error as write().
    void write_row(std::size_t layer, const GpkgValues& values, const GpkgGeometry& geometry);
    /// Inserts every queued row. Throws io_error as write().
    void flush_rows();
    /// A feature SQLite refused as a row (problem 902): its layer, input FID and GDAL's message.
    struct Refusal {
        std::size_t layer = 0;
        std::int64_t fid = 0;
        std::string message;
    };
    /// The refusals found since the last call, in input order within a layer.
    std::vector<Refusal> take_refusals();
    /// write() to the first (or only) layer.
    std::string write(const OGRFeature& source, std::int64_t fid, OGRGeometry* geometry)
    {
        return write(0, source, fid, geometry);
    }
    /// Closes the dataset, checks every write and the close, flushes the files to disk and
    /// renames them into place (or stages them in options.commit_group). Throws io_error, and
    /// argument_error when OUT appeared meanwhile without --overwrite.
    void commit();
    /// After commit(): OUT is where it belongs already (streamed to stdout, its transaction
    /// committed in an existing OUT, or renamed without a commit group), so nothing can take it
    /// back; false while its files wait in options.commit_group for the group's commit().
    bool output_in_place() const { return m_committed && (m_streamed || m_in_place || m_options.commit_group == nullptr); }

    /// Problems 903 (values the format changed) and 904 (renamed fields) found so far, each
    /// with its layer's index in Problem::layer.
    std::vector<Problem> take_problems();
    /// One line per field and kind of change, for a warning on stderr (with several layers,
    /// each starts with "layer 'x': ").
    std::vector<std::string> warnings() const;

    const std::string& driver_name() const { return m_driver_name; }
    std::size_t written() const;                    ///< in all layers
    std::size_t written(std::size_t layer) const;

private:
    /// One output layer and what it takes to write a source layer's features into it.
    struct Target {
        OGRLayer* layer = nullptr; ///< gone once the dataset is closed (commit)
        std::string name;
        std::vector<int> field_map;
        std::unique_ptr<FieldFidelity> fidelity;
        int orig_fid_field = -1;
        bool keeps_fids = false;
        std::size_t written = 0; ///< through GDAL, and the rows once the layer is finished
        /// A new GeoPackage layer's spatial index, written by finish() (io/gpkg_rtree.hpp).
        std::unique_ptr<GpkgIndexBuilder> index;
        /// A new GeoPackage layer's rows, when it can take them (io/gpkg_rows.hpp).
        std::unique_ptr<GpkgRows> rows;
    };

    void create_dataset(GDALDriver& driver);
    void open_in_place(GDALDriver& driver);
    void add_target(GDALDriver& driver, OGRLayer& source, bool renumber);
    bool take_existing(Target& t, OGRLayer& source);
    void delete_layer(const std::string& name);
    const char* outcome() const;
    void create_layer(Target& t, OGRLayer& source, std::vector<std::string> options);
    void create_fields(Target& t, const OGRFeatureDefn& source);
    void open_rows(Target& t, const OGRFeatureDefn& source, const std::vector<std::string>& options);
    void flush_rows(Target& t);
    void throw_if_write_failed() const;
    [[noreturn]] void fail_finishing(const std::string& gdal_message) const;
    void finish();
    void stage_files(CommitGroup& group);

    WriteOptions m_options;
    std::filesystem::path m_target;
    TempDirectory m_temp;           ///< first: exists before, and is removed after, everything below
    bool m_streamed = false;        ///< OUT is stdout: written as it goes, no temporary or rename
    bool m_in_place = false;        ///< OUT exists and is updated in its transaction, no temporary or rename
    std::filesystem::path m_failure_scope; ///< where a failed write counts: OUT's directory in place, else m_temp
    GDALDatasetUniquePtr m_dataset; ///< closed before m_temp is removed
    std::vector<Target> m_targets;  ///< one per source layer, in order
    std::string m_driver_name;
    std::vector<Problem> m_problems;
    std::vector<Refusal> m_refusals; ///< rows refused, not yet taken
    bool m_in_transaction = false;
    bool m_committed = false;
};

} // namespace trisnap
