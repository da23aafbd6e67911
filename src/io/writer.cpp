#include "io/writer.hpp"

#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/output_driver.hpp"

#include <cpl_conv.h>
#include <cpl_string.h>

#include <algorithm>
#include <unistd.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

bool has_option(const std::vector<std::string>& options, const std::string& key)
{
    return std::any_of(options.begin(), options.end(), [&](const std::string& o) {
        return o.size() > key.size() && o[key.size()] == '=' &&
               EQUALN(o.c_str(), key.c_str(), key.size());
    });
}

bool driver_has_layer_option(GDALDriver& driver, const std::string& key)
{
    const char* list = driver.GetMetadataItem(GDAL_DS_LAYER_CREATIONOPTIONLIST);
    return list && std::string(list).find("name='" + key + "'") != std::string::npos;
}

/// A field name for the original FID that does not clash with an existing field.
std::string orig_fid_name(const OGRFeatureDefn& defn)
{
    std::string name = "orig_fid";
    for (int i = 1; defn.GetFieldIndex(name.c_str()) >= 0; ++i) name = "orig_fid_" + std::to_string(i);
    return name;
}

struct StringList {
    explicit StringList(const std::vector<std::string>& items)
    {
        for (const auto& item : items) m_list = CSLAddString(m_list, item.c_str());
    }
    ~StringList() { CSLDestroy(m_list); }
    char** get() const { return m_list; }
    char** m_list = nullptr;
};

} // namespace

LayerWriter::LayerWriter(const WriteOptions& options, OGRLayer& source)
    : m_options(options), m_target(options.path)
{
    GDALDriver& driver = output_driver(options.path, options.format);
    m_driver_name = driver.GetDescription();
    m_keeps_fids = driver_keeps_fids(driver) && !options.renumber;
    // GeoPackage stamps the current time into gpkg_contents; a fixed date makes bytes repeatable.
    if (!CPLGetConfigOption("OGR_CURRENT_DATE", nullptr))
        CPLSetConfigOption("OGR_CURRENT_DATE", "2000-01-01T00:00:00.000Z");
    create_dataset(driver);
    create_layer(source, layer_options(driver, source));
    create_fields(*source.GetLayerDefn());
    if (m_dataset->TestCapability(ODsCTransactions))
        m_in_transaction = m_dataset->StartTransaction() == OGRERR_NONE;
}

LayerWriter::~LayerWriter()
{
    if (m_committed) return;
    ScopedErrorCapture quiet; // closing a half-written dataset may complain; it is deleted anyway
    m_dataset.reset();
    std::error_code ec;
    fs::remove_all(m_temp_dir, ec);
}

void LayerWriter::create_dataset(GDALDriver& driver)
{
    const bool streamed = is_stdout_path(m_options.path); // written as it goes: no temporary, no rename
    const fs::path parent = m_target.has_parent_path() ? m_target.parent_path() : fs::path(".");
    std::string name = ".";
    name.append(m_target.filename().string()).append(".trisnap-tmp-").append(std::to_string(getpid()));
    m_temp_dir = streamed ? fs::path() : parent / name;
    std::error_code ec;
    fs::remove_all(m_temp_dir, ec);
    if (!streamed && !fs::create_directory(m_temp_dir, ec))
        throw io_error(m_options.path, "", "cannot create temporary directory " + m_temp_dir.string() + ": " + ec.message());
    const std::string temp_path = streamed ? stdout_dataset_path(driver) : (m_temp_dir / m_target.filename()).string();
    const StringList dataset_options(m_options.dataset_options);
    ScopedErrorCapture capture;
    m_dataset.reset(driver.Create(temp_path.c_str(), 0, 0, 0, GDT_Unknown, dataset_options.get()));
    if (!m_dataset) throw io_error(m_options.path, "", capture.last_error("cannot create the dataset"));
}

std::vector<std::string> LayerWriter::layer_options(GDALDriver& driver, OGRLayer& source) const
{
    std::vector<std::string> options = m_options.layer_options;
    const std::string fid_column = source.GetFIDColumn();
    if (!fid_column.empty() && !has_option(options, "FID") && driver_has_layer_option(driver, "FID"))
        options.push_back("FID=" + fid_column);
    const std::string geometry_column = source.GetGeometryColumn();
    if (!geometry_column.empty() && !has_option(options, "GEOMETRY_NAME") &&
        driver_has_layer_option(driver, "GEOMETRY_NAME"))
        options.push_back("GEOMETRY_NAME=" + geometry_column);
    // Shapefiles stamp today's date in the .dbf header; a fixed date makes bytes repeatable.
    if (!has_option(options, "DBF_DATE_LAST_UPDATE") && driver_has_layer_option(driver, "DBF_DATE_LAST_UPDATE"))
        options.push_back("DBF_DATE_LAST_UPDATE=2000-01-01");
    // GeoJSON defaults to 15 significant digits, which can move snapped vertices; keep them exact.
    if (!has_option(options, "SIGNIFICANT_FIGURES") && !has_option(options, "COORDINATE_PRECISION") &&
        driver_has_layer_option(driver, "SIGNIFICANT_FIGURES"))
        options.push_back("SIGNIFICANT_FIGURES=17");
    // FlatGeobuf's spatial index sorts features along a Hilbert curve; without it they stay in input order.
    if (!has_option(options, "SPATIAL_INDEX") && m_driver_name == "FlatGeobuf")
        options.push_back("SPATIAL_INDEX=NO");
    // OGR hands us UTF-8; without this the Shapefile driver would recode to ISO-8859-1.
    if (!has_option(options, "ENCODING") && driver_has_layer_option(driver, "ENCODING") &&
        m_driver_name == "ESRI Shapefile")
        options.push_back("ENCODING=UTF-8");
    return options;
}

void LayerWriter::create_layer(OGRLayer& source, const std::vector<std::string>& options)
{
    const std::string name = m_options.layer_name.empty() ? source.GetName() : m_options.layer_name;
    const StringList list(options);
    ScopedErrorCapture capture;
    m_layer = m_dataset->CreateLayer(name.c_str(), source.GetSpatialRef(), source.GetGeomType(), list.get());
    if (!m_layer) throw io_error(m_options.path, name, capture.last_error("cannot create the layer"));
}

void LayerWriter::create_fields(const OGRFeatureDefn& source)
{
    ScopedErrorCapture capture;
    for (int i = 0; i < source.GetFieldCount(); ++i) {
        OGRFieldDefn field(source.GetFieldDefn(i));
        const auto& only = m_options.fields; // --select: the others map to -1, which SetFieldsFrom skips
        if (!only.empty() && std::find(only.begin(), only.end(), field.GetNameRef()) == only.end()) {
            m_field_map.push_back(-1);
            continue;
        }
        if (m_layer->CreateField(&field, TRUE) != OGRERR_NONE)
            throw io_error(m_options.path, m_layer->GetName(),
                           "cannot create field '" + std::string(field.GetNameRef()) + "': " + capture.last_error());
        m_field_map.push_back(m_layer->GetLayerDefn()->GetFieldCount() - 1);
    }
    if (m_keeps_fids) return;
    OGRFieldDefn orig(orig_fid_name(source).c_str(), OFTInteger64);
    if (m_layer->CreateField(&orig) != OGRERR_NONE)
        throw io_error(m_options.path, m_layer->GetName(), "cannot create field orig_fid: " + capture.last_error());
    m_orig_fid_field = m_layer->GetLayerDefn()->GetFieldCount() - 1;
}

std::string LayerWriter::write(const OGRFeature& source, std::int64_t fid, OGRGeometry* geometry)
{
    OGRFeatureUniquePtr out(OGRFeature::CreateFeature(m_layer->GetLayerDefn()));
    out->SetFieldsFrom(&source, m_field_map.data(), TRUE);
    if (m_orig_fid_field >= 0) out->SetField(m_orig_fid_field, static_cast<GIntBig>(fid));
    if (m_keeps_fids) out->SetFID(fid);
    out->SetGeometryDirectly(geometry);
    ScopedErrorCapture capture;
    if (m_layer->CreateFeature(out.get()) != OGRERR_NONE)
        return capture.last_error("the driver refused the feature");
    ++m_written;
    return "";
}

void LayerWriter::commit()
{
    ScopedErrorCapture capture;
    if (m_in_transaction && m_dataset->CommitTransaction() != OGRERR_NONE)
        throw io_error(m_options.path, "", capture.last_error("cannot commit the transaction"));
    m_dataset.reset(); // GDALClose: some drivers (FlatGeobuf) write everything here
    if (!capture.errors().empty()) throw io_error(m_options.path, "", capture.last_error());
    if (!m_temp_dir.empty()) move_into_place();
    m_committed = true;
}

void LayerWriter::move_into_place()
{
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(m_temp_dir)) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    const fs::path parent = m_target.has_parent_path() ? m_target.parent_path() : fs::path(".");
    // Multi-file formats (Shapefile): remove every old component, not just the main file.
    if (files.size() > 1 && fs::exists(m_target)) GDALDriver::QuietDelete(m_target.string().c_str());
    std::error_code ec;
    for (const fs::path& file : files) {
        fs::rename(file, parent / file.filename(), ec);
        if (ec) throw io_error(m_options.path, "", "cannot move the result into place: " + ec.message());
    }
    fs::remove_all(m_temp_dir, ec);
}

} // namespace trisnap
