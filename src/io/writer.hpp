#pragma once
// Writes the snapped layer like ogr2ogr would: same layer name (unless renamed), fields, field
// types and values, CRS and FIDs (or an `orig_fid` field where the format renumbers features).
// Everything goes to a temporary directory beside the target and is renamed into place by
// commit(), so an interrupted run never leaves a half-written file at the target path.
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cstdint>
#include <filesystem>
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
    bool renumber = false; ///< input FIDs unusable (duplicate or missing): always add orig_fid
};

/// The driver for `path` (format empty: from the extension, like ogr2ogr). Throws
/// argument_error when the format is unknown or cannot create vector datasets.
GDALDriver& output_driver(const std::string& path, const std::string& format);

/// Refuses an existing target without overwrite and a missing parent directory.
void check_output_path(const WriteOptions& options, const std::string& input_path);

/// True when the driver stores the FIDs we set (else the writer adds `orig_fid`).
bool driver_keeps_fids(GDALDriver& driver);

class LayerWriter {
public:
    LayerWriter(const WriteOptions& options, OGRLayer& source);
    ~LayerWriter(); ///< removes the temporary directory unless commit() succeeded
    LayerWriter(const LayerWriter&) = delete;
    LayerWriter& operator=(const LayerWriter&) = delete;

    /// Writes the attributes of `source` (by field index) with `geometry` (ownership taken,
    /// may be null). Returns "" on success, else the driver's message (problem 902).
    std::string write(const OGRFeature& source, std::int64_t fid, OGRGeometry* geometry);
    /// Finishes the dataset and renames it into place. Throws io_error.
    void commit();

    bool keeps_fids() const { return m_keeps_fids; }
    const std::string& driver_name() const { return m_driver_name; }
    std::size_t written() const { return m_written; }

private:
    void create_dataset(GDALDriver& driver);
    void create_layer(OGRLayer& source, const std::vector<std::string>& options);
    void create_fields(const OGRFeatureDefn& source);
    std::vector<std::string> layer_options(GDALDriver& driver, OGRLayer& source) const;
    void move_into_place();

    WriteOptions m_options;
    std::filesystem::path m_target;
    std::filesystem::path m_temp_dir;
    GDALDatasetUniquePtr m_dataset;
    OGRLayer* m_layer = nullptr;
    std::string m_driver_name;
    std::vector<int> m_field_map;
    int m_orig_fid_field = -1;
    bool m_keeps_fids = false;
    bool m_in_transaction = false;
    bool m_committed = false;
    std::size_t m_written = 0;
};

} // namespace trisnap
