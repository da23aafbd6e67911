#include "io/writer.hpp"

#include "config/errors.hpp"
#include "io/checked_files.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/layer_options.hpp"
#include "io/output_driver.hpp"
#include "io/update_target.hpp"

#include <cpl_conv.h>
#include <cpl_string.h>

#include <algorithm>
#include <utility>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

/// A field name for the original FID that does not clash with an existing field.
std::string orig_fid_name(const OGRFeatureDefn& defn)
{
    std::string name = "orig_fid";
    for (int i = 1; defn.GetFieldIndex(name.c_str()) >= 0; ++i) {
        name = "orig_fid_" + std::to_string(i);
    }
    return name;
}

struct StringList {
    explicit StringList(const std::vector<std::string>& items)
    {
        for (const auto& item : items) {
            m_list = CSLAddString(m_list, item.c_str());
        }
    }
    ~StringList() { CSLDestroy(m_list); }
    char** get() const { return m_list; }
    char** m_list = nullptr;
};

fs::path parent_of(const fs::path& target)
{
    return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

/// Drivers' own temporary files (FlatGeobuf's feature spool, created through CPL_TMPDIR, else
/// in the current directory) go here, inside our temporary directory: checked like OUT, and
/// gone with it. Never part of the result.
constexpr const char* k_scratch = ".scratch";

/// The files of the result: what the driver left in the temporary directory.
std::vector<fs::path> result_files(const fs::path& directory)
{
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(directory)) {
        if (entry.path().filename() != k_scratch) {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Points CPL_TMPDIR (for this thread, while it lives) at the scratch directory.
class ScratchDirectory {
public:
    explicit ScratchDirectory(const fs::path& temp_dir)
    {
        const char* previous = CPLGetThreadLocalConfigOption("CPL_TMPDIR", nullptr);
        m_had_previous = previous != nullptr;
        m_previous = previous ? previous : "";
        std::error_code ec;
        fs::create_directory(temp_dir / k_scratch, ec);
        CPLSetThreadLocalConfigOption("CPL_TMPDIR", checked_path(temp_dir / k_scratch).c_str());
    }
    ~ScratchDirectory()
    {
        CPLSetThreadLocalConfigOption("CPL_TMPDIR", m_had_previous ? m_previous.c_str() : nullptr);
    }
    ScratchDirectory(const ScratchDirectory&) = delete;
    ScratchDirectory& operator=(const ScratchDirectory&) = delete;

private:
    std::string m_previous;
    bool m_had_previous = false;
};

/// GeoPackage, unless the user asked for no index (-lco SPATIAL_INDEX=NO): GDAL is told NO and
/// the writer bulk loads the index itself at the end (io/gpkg_rtree.hpp).
bool bulk_loads_index(const std::string& driver_name, std::vector<std::string>& options)
{
    if (driver_name != "GPKG") {
        return false;
    }
    const std::string key = "SPATIAL_INDEX=";
    const auto given = std::find_if(options.begin(), options.end(), [&](const std::string& o) {
        return o.size() >= key.size() && EQUALN(o.c_str(), key.c_str(), key.size());
    });
    if (given == options.end()) {
        options.push_back(key + "NO");
        return true;
    }
    if (!CPLTestBool(given->c_str() + key.size())) {
        return false;
    }
    *given = key + "NO";
    return true;
}

} // namespace

LayerWriter::LayerWriter(const WriteOptions& options, const std::vector<OGRLayer*>& sources)
    : m_options(options), m_target(options.path),
      // A streamed OUT keeps its scratch files (a driver's spool) beside the current directory.
      m_temp(is_stdout_path(options.path) ? std::filesystem::path("stdout") : m_target, options.path),
      m_streamed(is_stdout_path(options.path))
{
    GDALDriver& driver = output_driver(options.path, options.format);
    m_driver_name = driver.GetDescription();
    // GeoPackage stamps the current time into gpkg_contents; a fixed date makes bytes repeatable.
    if (!CPLGetConfigOption("OGR_CURRENT_DATE", nullptr)) {
        CPLSetConfigOption("OGR_CURRENT_DATE", "2000-01-01T00:00:00.000Z");
    }
    // CSV writes the geometry as WKT with 15 significant digits, which can move snapped vertices.
    if (m_driver_name == "CSV" && !CPLGetConfigOption("OGR_WKT_PRECISION", nullptr)) {
        CPLSetConfigOption("OGR_WKT_PRECISION", "17");
    }
    const ScratchDirectory scratch(m_temp.path());
    m_in_place = updates_in_place(options, driver);
    m_failure_scope = m_in_place ? parent_of(fs::absolute(m_target)) : m_temp.path();
    if (m_in_place) {
        open_in_place(driver);
    } else {
        create_dataset(driver);
    }
    m_targets.reserve(sources.size());
    for (std::size_t k = 0; k < sources.size(); ++k) {
        add_target(driver, *sources[k], k < options.renumber.size() && options.renumber[k]);
    }
    if (!m_in_place && m_dataset->TestCapability(ODsCTransactions)) {
        m_in_transaction = m_dataset->StartTransaction() == OGRERR_NONE;
    }
}

// The output layer of one source: created (an existing one replaced first with --overwrite),
// or, with --append, the existing one.
void LayerWriter::add_target(GDALDriver& driver, OGRLayer& source, bool renumber)
{
    Target& t = m_targets.emplace_back();
    t.keeps_fids = driver_keeps_fids(driver) && !renumber;
    if (!m_in_place || !take_existing(t, source)) {
        const std::vector<std::string> options = creation_options(m_options.layer_options, driver, source);
        create_layer(t, source, options);
        create_fields(t, *source.GetLayerDefn());
        open_rows(t, *source.GetLayerDefn(), options);
    }
    t.name = t.layer->GetName();
    t.fidelity = std::make_unique<FieldFidelity>(*source.GetLayerDefn(), *t.layer->GetLayerDefn(), t.field_map,
                                                 m_driver_name);
    for (Problem p : t.fidelity->renamed_fields()) {
        p.layer = static_cast<std::uint32_t>(m_targets.size() - 1);
        m_problems.push_back(std::move(p));
    }
}

LayerWriter::~LayerWriter()
{
    if (m_committed) {
        return;
    }
    ScopedErrorCapture quiet; // closing a half-written dataset may complain; it is deleted anyway
    if (m_in_place && m_in_transaction) {
        m_dataset->RollbackTransaction(); // an existing OUT stays as it was
    }
    m_dataset.reset();
    // m_temp, destroyed after this body, removes the directory with everything in it.
}

void LayerWriter::create_dataset(GDALDriver& driver)
{
    // Through the checking file system: drivers that ignore failed writes cannot hide them. A
    // streamed OUT (stdout) is written as it goes: no temporary, no rename.
    const std::string temp_path = m_streamed ? stdout_dataset_path(driver) : checked_path(m_temp.path() / m_target.filename());
    const StringList dataset_options(m_options.dataset_options);
    ScopedErrorCapture capture;
    m_dataset.reset(driver.Create(temp_path.c_str(), 0, 0, 0, GDT_Unknown, dataset_options.get()));
    if (!m_dataset) {
        throw io_error(m_options.path, "", capture.last_error("cannot create the dataset"));
    }
}

// An existing OUT that holds layers: everything from here to commit() is one transaction.
void LayerWriter::open_in_place(GDALDriver& driver)
{
    m_dataset = open_for_update(m_options, driver);
    ScopedErrorCapture capture;
    if (m_dataset->StartTransaction() != OGRERR_NONE) {
        throw io_error(m_options.path, "", capture.last_error("cannot start a transaction to update it"));
    }
    m_in_transaction = true;
}

// In an existing OUT: true when the features go into the layer already there (--append); an
// existing layer is deleted otherwise (--overwrite; check_update_target refused it without).
bool LayerWriter::take_existing(Target& t, OGRLayer& source)
{
    const std::string name = output_layer_name(m_options, source);
    OGRLayer* existing = m_dataset->GetLayerByName(name.c_str());
    if (existing != nullptr && m_options.append) {
        // The layer's own FIDs go on; the input FID goes into its orig_fid field when it has one.
        t.layer = existing;
        t.keeps_fids = false;
        t.field_map = append_field_map(*source.GetLayerDefn(), *t.layer->GetLayerDefn(), m_options.fields,
                                       m_options.path + " (layer '" + name + "')");
        t.orig_fid_field = t.layer->GetLayerDefn()->GetFieldIndex("orig_fid");
        return true;
    }
    if (existing != nullptr) {
        delete_layer(name);
    }
    return false;
}

void LayerWriter::delete_layer(const std::string& name)
{
    ScopedErrorCapture capture;
    for (int i = 0; i < m_dataset->GetLayerCount(); ++i) {
        if (name == m_dataset->GetLayer(i)->GetName() && m_dataset->DeleteLayer(i) == OGRERR_NONE) {
            return;
        }
    }
    throw io_error(m_options.path, name, capture.last_error("cannot delete the layer to replace it"));
}

void LayerWriter::create_layer(Target& t, OGRLayer& source, std::vector<std::string> options)
{
    if (bulk_loads_index(m_driver_name, options)) {
        // Above the box budget the boxes are sorted in runs on disk, in the scratch directory
        // beside OUT's temporary file (removed with it).
        t.index = std::make_unique<GpkgIndexBuilder>(m_options.index_boxes, m_temp.path() / k_scratch, m_options.path);
    }
    const std::string name = m_options.layer_name.empty() ? source.GetName() : m_options.layer_name;
    const StringList list(options);
    ScopedErrorCapture capture;
    t.layer = m_dataset->CreateLayer(name.c_str(), source.GetSpatialRef(), source.GetGeomType(), list.get());
    if (!t.layer) {
        throw io_error(m_options.path, name, capture.last_error("cannot create the layer"));
    }
    if (t.layer->GetLayerDefn()->GetGeomFieldCount() == 0) {
        throw argument_error(m_options.path + ": the " + m_driver_name +
                             " format cannot store the geometries; choose another format (e.g. -f GPKG)");
    }
}

void LayerWriter::create_fields(Target& t, const OGRFeatureDefn& source)
{
    ScopedErrorCapture capture;
    for (int i = 0; i < source.GetFieldCount(); ++i) {
        OGRFieldDefn field(source.GetFieldDefn(i));
        const auto& only = m_options.fields; // --select: the others map to -1, which SetFieldsFrom skips
        if (!only.empty() && std::find(only.begin(), only.end(), field.GetNameRef()) == only.end()) {
            t.field_map.push_back(-1);
            continue;
        }
        if (t.layer->CreateField(&field, TRUE) != OGRERR_NONE) {
            throw io_error(m_options.path, t.layer->GetName(),
                           "cannot create field '" + std::string(field.GetNameRef()) + "': " + capture.last_error());
        }
        t.field_map.push_back(t.layer->GetLayerDefn()->GetFieldCount() - 1);
    }
    if (t.keeps_fids) {
        return;
    }
    OGRFieldDefn orig(orig_fid_name(source).c_str(), OFTInteger64);
    if (t.layer->CreateField(&orig) != OGRERR_NONE) {
        throw io_error(m_options.path, t.layer->GetName(), "cannot create field orig_fid: " + capture.last_error());
    }
    t.orig_fid_field = t.layer->GetLayerDefn()->GetFieldCount() - 1;
}

// A new GeoPackage layer takes rows where it can: in a new OUT, or made in an existing one by
// --overwrite or --update (the rows go into the transaction open_in_place() started, and a
// failure rolls them back with the rest; --append's existing layer is not new).
void LayerWriter::open_rows(Target& t, const OGRFeatureDefn& source, const std::vector<std::string>& options)
{
    if (!m_options.rows || m_streamed) {
        return;
    }
    std::vector<int> source_of(static_cast<std::size_t>(t.layer->GetLayerDefn()->GetFieldCount()), -1);
    for (std::size_t i = 0; i < t.field_map.size(); ++i) {
        if (t.field_map[i] >= 0 && static_cast<std::size_t>(t.field_map[i]) < source_of.size()) {
            source_of[static_cast<std::size_t>(t.field_map[i])] = static_cast<int>(i);
        }
    }
    try {
        t.rows = GpkgRows::open(*m_dataset, *t.layer, source, source_of, t.keeps_fids, options, m_options.path,
                                t.index.get());
    } catch (const io_error&) {
        throw_if_write_failed(); // the table is created here: a full disk says more than SQLite
        throw;
    }
}

const char* LayerWriter::outcome() const
{
    return m_in_place ? "; OUT was left as it was (its transaction rolled back)" : "; nothing was left at OUT";
}

void LayerWriter::throw_if_write_failed() const
{
    // After every feature: free while nothing failed (the scope is made once, in the constructor;
    // made here each time it was 3 % of write_lending's time).
    const std::string failure = take_write_failure(m_failure_scope);
    if (!failure.empty()) {
        throw io_error(m_options.path, "", "cannot write (" + failure + ")" + outcome());
    }
}

void LayerWriter::fail_finishing(const std::string& gdal_message) const
{
    throw_if_write_failed(); // the cause (a full disk) says more than the driver's complaint about it
    throw io_error(m_options.path, "", gdal_message + outcome());
}

void LayerWriter::expect(std::size_t layer, std::size_t features)
{
    if (layer < m_targets.size() && m_targets[layer].index) {
        m_targets[layer].index->reserve(features);
    }
}

std::string LayerWriter::write(std::size_t layer, const OGRFeature& source, std::int64_t fid, OGRGeometry* geometry)
{
    std::unique_ptr<OGRGeometry> owned(geometry);
    return write_lending(layer, source, fid, owned);
}

std::string LayerWriter::write_lending(std::size_t layer, const OGRFeature& source, std::int64_t fid,
                                       std::unique_ptr<OGRGeometry>& geometry)
{
    Target& t = m_targets[layer];
    if (t.rows) {
        flush_rows(t); // the rows queued before this feature go in before it
    }
    ScopedErrorCapture capture;
    OGRFeatureUniquePtr out(OGRFeature::CreateFeature(t.layer->GetLayerDefn()));
    out->SetFieldsFrom(&source, t.field_map.data(), TRUE);
    if (t.orig_fid_field >= 0) {
        out->SetField(t.orig_fid_field, static_cast<GIntBig>(fid));
    }
    if (t.keeps_fids) {
        out->SetFID(fid);
    }
    out->SetGeometryDirectly(geometry.release());
    struct GiveBack { // on every way out, the geometry goes back to the caller
        OGRFeature& out;
        std::unique_ptr<OGRGeometry>& geometry;
        ~GiveBack() { geometry.reset(out.StealGeometry()); }
    } give_back{*out, geometry};
    const bool refused = t.layer->CreateFeature(out.get()) != OGRERR_NONE;
    throw_if_write_failed();
    if (refused && m_in_place) {
        // Inside the transaction a refusal cannot be told from a failed write (SQLite may even
        // have ended the transaction): stop and roll back rather than commit half a layer.
        throw io_error(m_options.path, t.layer->GetName(), "feature " + std::to_string(fid) + ": " +
                       capture.last_error("the driver refused the feature") + outcome());
    }
    if (refused) {
        return capture.last_error("the driver refused the feature");
    }
    if (t.index) {
        t.index->add(out->GetFID(), out->GetGeometryRef());
    }
    if (t.rows) {
        t.rows->include(out->GetGeometryRef()); // GDAL's extent is overwritten by the rows' (finish)
    }
    const std::size_t first = m_problems.size();
    t.fidelity->check(source, *out, fid, m_problems);
    for (std::size_t i = first; i < m_problems.size(); ++i) {
        m_problems[i].layer = static_cast<std::uint32_t>(layer);
    }
    ++t.written;
    return "";
}

// The same accounting as write_lending's, without the OGR feature: the layer's fields have the
// input's types (GpkgRows::open), so FieldFidelity would find nothing to report. The index and
// the count take the row when its batch went in.
void LayerWriter::write_row(std::size_t layer, const GpkgValues& values, const GpkgGeometry& geometry)
{
    Target& t = m_targets[layer];
    try {
        t.rows->insert(values, geometry);
    } catch (const io_error&) {
        throw_if_write_failed(); // a full disk says more than SQLite's complaint about it
        throw;
    }
    throw_if_write_failed();
    for (GpkgRows::Refusal& r : t.rows->take_refusals()) {
        m_refusals.push_back({layer, r.fid, std::move(r.message)});
    }
}

void LayerWriter::flush_rows(Target& t)
{
    try {
        t.rows->flush();
    } catch (const io_error&) {
        throw_if_write_failed();
        throw;
    }
    throw_if_write_failed();
    const auto layer = static_cast<std::size_t>(&t - m_targets.data());
    for (GpkgRows::Refusal& r : t.rows->take_refusals()) {
        m_refusals.push_back({layer, r.fid, std::move(r.message)});
    }
}

void LayerWriter::flush_rows()
{
    for (Target& t : m_targets) {
        if (t.rows) {
            flush_rows(t);
        }
    }
}

std::vector<LayerWriter::Refusal> LayerWriter::take_refusals()
{
    return std::exchange(m_refusals, {});
}

std::size_t LayerWriter::written(std::size_t layer) const
{
    const Target& t = m_targets[layer];
    return t.written + (t.rows ? t.rows->inserted() : 0);
}

std::vector<Problem> LayerWriter::take_problems()
{
    return std::exchange(m_problems, {});
}

std::vector<std::string> LayerWriter::warnings() const
{
    std::vector<std::string> lines;
    for (const Target& t : m_targets) {
        const std::string prefix = m_targets.size() > 1 ? "layer '" + t.name + "': " : "";
        for (const std::string& line : t.fidelity->summary()) {
            lines.push_back(prefix + line);
        }
    }
    return lines;
}

std::size_t LayerWriter::written() const
{
    std::size_t n = 0;
    for (std::size_t k = 0; k < m_targets.size(); ++k) {
        n += written(k);
    }
    return n;
}

void LayerWriter::finish()
{
    const ScratchDirectory scratch(m_temp.path());
    CPLErrorReset();
    ScopedErrorCapture capture;
    for (Target& t : m_targets) {
        if (t.rows) {
            flush_rows(t);
            try {
                t.rows->finish(written(static_cast<std::size_t>(&t - m_targets.data())));
            } catch (const io_error&) {
                throw_if_write_failed();
                throw;
            }
            t.written += t.rows->inserted();
            t.rows.reset();
        }
        if (t.index) {
            try {
                t.index->write(*m_dataset, *t.layer, m_options.path, outcome());
            } catch (const io_error&) {
                throw_if_write_failed(); // a full disk says more than SQLite's complaint about it
                throw;
            }
            t.index.reset();
        }
    }
    if (m_in_transaction && m_dataset->CommitTransaction() != OGRERR_NONE) {
        fail_finishing(capture.last_error("cannot commit the transaction"));
    }
    m_in_transaction = false;
    m_dataset.reset(); // GDALClose: some drivers (FlatGeobuf) write everything here
    if (!capture.errors().empty() || CPLGetLastErrorType() >= CE_Failure) {
        fail_finishing(capture.last_error(CPLGetLastErrorMsg()));
    }
    throw_if_write_failed();
    if (m_streamed || m_in_place) {
        return;
    }
    if (result_files(m_temp.path()).empty()) {
        throw argument_error(m_options.path + ": the " + m_driver_name + " driver wrote no file; choose a file format");
    }
    sync_tree(m_temp.path(), m_options.path);
}

void LayerWriter::stage_files(CommitGroup& group)
{
    const std::vector<fs::path> files = result_files(m_temp.path());
    // Multi-file formats (Shapefile): remove every old component, not just the main file.
    if (files.size() > 1 && m_options.overwrite && fs::exists(m_target)) {
        group.replace_dataset(m_target);
    }
    for (const fs::path& file : files) {
        group.stage(file, parent_of(m_target) / file.filename(), m_options.overwrite, "OUT");
    }
    group.protect(m_options.protected_files);
    group.own_directory(m_temp.release());
}

void LayerWriter::commit()
{
    finish();
    if (m_streamed || m_in_place) {
        m_committed = true; // OUT is in place: streamed, or its transaction committed
        return;
    }
    if (m_options.commit_group != nullptr) {
        stage_files(*m_options.commit_group);
    } else {
        CommitGroup group;
        stage_files(group);
        group.commit();
    }
    m_committed = true;
}

} // namespace trisnap
