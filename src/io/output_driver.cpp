// Choosing and checking the output format and path (the part of the writer that runs before
// any data is read, so `validate` can use it without writing anything).
#include "io/output_driver.hpp"

#include "config/errors.hpp"
#include "io/format_limits.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"

#include <cpl_string.h>
#include <cpl_vsi.h>

#include <algorithm>
#include <sstream>
#include <unistd.h>

namespace trisnap {
namespace {

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool lists_extension(GDALDriver& driver, const std::string& ext)
{
    const char* list = driver.GetMetadataItem(GDAL_DMD_EXTENSIONS);
    std::istringstream words(list ? list : "");
    for (std::string word; words >> word;)
        if (lower(word) == ext) return true;
    return false;
}

std::string first_extension(GDALDriver& driver)
{
    const char* list = driver.GetMetadataItem(GDAL_DMD_EXTENSIONS);
    std::istringstream words(list ? list : "");
    std::string word;
    words >> word;
    return word;
}

GDALDriver* driver_for_extension(const std::string& ext)
{
    GDALDriverManager* manager = GetGDALDriverManager();
    for (int i = 0; i < manager->GetDriverCount(); ++i) {
        GDALDriver* driver = manager->GetDriver(i);
        if (can_write_vector(*driver) && lists_extension(*driver, ext)) return driver;
    }
    return nullptr;
}


/// "-" streams GeoJSON unless -f says otherwise; a driver that must seek cannot stream.
GDALDriver& stdout_driver(const std::string& format)
{
    const std::string name = format.empty() ? "GeoJSON" : format;
    GDALDriver& driver = output_driver("", name);
    if (!can_stream(driver)) {
        throw argument_error(std::string("OUT - (stdout): the ") + driver.GetDescription() +
                             " driver cannot stream (it needs to seek in its file); give a file name, or -f GeoJSON, "
                             "GeoJSONSeq or FlatGeobuf");
    }
    return driver;
}

class StringList {
public:
    explicit StringList(const std::vector<std::string>& items)
    {
        for (const std::string& item : items) {
            m_list.AddString(item.c_str());
        }
    }
    char** get() { return m_list.List(); }

private:
    CPLStringList m_list;
};

void check_selected_fields(const std::vector<std::string>& fields, OGRFeatureDefn& defn)
{
    for (const std::string& name : fields) {
        if (defn.GetFieldIndex(name.c_str()) >= 0) {
            continue;
        }
        std::string known;
        for (int i = 0; i < defn.GetFieldCount(); ++i) {
            known += (i == 0 ? "" : ", ") + std::string(defn.GetFieldDefn(i)->GetNameRef());
        }
        throw argument_error("--select: no field '" + name + "' in the input; fields: " + (known.empty() ? "none" : known));
    }
}

/// Layer and fields as the writer creates them, in `dataset`; "" or GDAL's complaint.
std::string create_probe_layer(GDALDataset& dataset, const WriteOptions& options, OGRLayer& source)
{
    const std::string name = options.layer_name.empty() ? source.GetName() : options.layer_name;
    StringList lco(options.layer_options);
    ScopedErrorCapture capture;
    OGRLayer* layer = dataset.CreateLayer(name.c_str(), source.GetSpatialRef(), source.GetGeomType(), lco.get());
    if (!layer) {
        return "cannot create layer '" + name + "' of type " + OGRGeometryTypeToName(source.GetGeomType()) + ": " +
               capture.last_error("no reason given");
    }
    OGRFeatureDefn& defn = *source.GetLayerDefn();
    for (int i = 0; i < defn.GetFieldCount(); ++i) {
        OGRFieldDefn field(defn.GetFieldDefn(i));
        const bool selected = options.fields.empty() ||
            std::find(options.fields.begin(), options.fields.end(), field.GetNameRef()) != options.fields.end();
        if (selected && layer->CreateField(&field, TRUE) != OGRERR_NONE) {
            return "cannot create field '" + std::string(field.GetNameRef()) + "': " + capture.last_error();
        }
    }
    return "";
}

/// A format that would lose what snapping made (io/format_limits.hpp) is refused by name.
void refuse_format(GDALDriver& driver, const std::string& what)
{
    const std::string reason = format_refusal(driver);
    if (!reason.empty()) {
        throw argument_error(what + ": the " + std::string(driver.GetDescription()) + " format " + reason);
    }
}

GDALDriver& driver_by_name(const std::string& format)
{
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(format.c_str());
    if (!driver) {
        throw argument_error("-f " + format + ": unknown GDAL format (trisnap --formats lists them)");
    }
    if (!can_write_vector(*driver)) {
        throw argument_error("-f " + format + ": this format cannot be written");
    }
    refuse_format(*driver, "-f " + format);
    return *driver;
}

} // namespace

bool is_stdout_path(const std::string& path)
{
    return path.rfind("/vsistdout/", 0) == 0;
}

bool can_write_vector(GDALDriver& driver)
{
    return driver.GetMetadataItem(GDAL_DCAP_VECTOR) && driver.GetMetadataItem(GDAL_DCAP_CREATE);
}

bool can_stream(GDALDriver& driver)
{
    const std::string name = driver.GetDescription();
    return name == "GeoJSON" || name == "GeoJSONSeq" || name == "FlatGeobuf";
}

std::string stdout_dataset_path(GDALDriver& driver)
{
    const std::string ext = first_extension(driver);
    return "/vsistdout/trisnap" + (ext.empty() ? "" : "." + ext);
}

void probe_output(GDALDriver& driver, const WriteOptions& options, OGRLayer& source)
{
    check_selected_fields(options.fields, *source.GetLayerDefn());
    if (!driver.GetMetadataItem(GDAL_DCAP_VIRTUALIO)) {
        return; // cannot be tried in memory; the writer reports what the driver says
    }
    const std::string dir = "/vsimem/trisnap-probe-" + std::to_string(getpid());
    std::string file = std::filesystem::path(options.path).filename().string();
    if (file.empty() || is_stdout_path(options.path)) {
        file = std::filesystem::path(stdout_dataset_path(driver)).filename().string();
    }
    VSIMkdir(dir.c_str(), 0755);
    std::string error;
    {
        StringList dsco(options.dataset_options);
        ScopedErrorCapture capture;
        GDALDatasetUniquePtr dataset(driver.Create((dir + "/" + file).c_str(), 0, 0, 0, GDT_Unknown, dsco.get()));
        error = dataset ? create_probe_layer(*dataset, options, source)
                        : capture.last_error("cannot create the dataset");
    }
    VSIRmdirRecursive(dir.c_str());
    if (!error.empty()) {
        throw argument_error(options.path + ": the " + driver.GetDescription() + " driver refuses it: " + error);
    }
    // A layer the driver takes but would reproject or round after snapping (io/format_limits.hpp).
    const std::string refusal = layer_refusal(driver, source.GetSpatialRef(), options.layer_options);
    if (!refusal.empty()) {
        const std::string out = is_stdout_path(options.path) ? "OUT - (stdout)" : options.path;
        throw argument_error(out + ": the " + std::string(driver.GetDescription()) + " format " + refusal);
    }
}

GDALDriver& output_driver(const std::string& path, const std::string& format)
{
    if (is_stdout_path(path)) {
        return stdout_driver(format);
    }
    if (!format.empty()) {
        return driver_by_name(format);
    }
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    GDALDriver* driver = ext.size() > 1 ? driver_for_extension(ext.substr(1)) : nullptr;
    if (!driver) {
        throw argument_error(path + ": cannot tell the output format from the extension '" + ext +
                             "'; give one with -f (e.g. -f GPKG)");
    }
    refuse_format(*driver, path);
    return *driver;
}

void check_output_files(const WriteOptions& options, GDALDriver& driver)
{
    options.protected_files.refuse(options.path, "OUT");
    for (const std::string& file : dataset_files_for(options.path, driver)) {
        const std::string owner = options.protected_files.owner_of(file);
        if (!owner.empty()) {
            throw argument_error("OUT " + options.path + ": writing it would replace " + file + ", a file of " + owner +
                                 "; choose another path");
        }
    }
}

void check_output_path(const WriteOptions& options, const std::string& input_path)
{
    namespace fs = std::filesystem;
    if (is_stdout_path(options.path)) {
        return; // nothing on disk to check or replace
    }
    const fs::path target(options.path);
    std::error_code ec;
    if (fs::exists(input_path, ec) && fs::exists(target, ec) && fs::equivalent(input_path, target, ec)) {
        throw argument_error(options.path + ": output is the input; choose another OUT");
    }
    if (fs::exists(target, ec) && !options.overwrite && !options.update && !options.append) {
        throw argument_error(options.path + ": already exists; add --overwrite to replace it (in a GPKG or SQLite file: "
                             "its layer of that name), or --update/--append to write into it");
    }
    if (fs::is_directory(target, ec)) {
        throw argument_error(options.path + ": is a directory; give a file name for OUT");
    }
    const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec)) {
        throw io_error(options.path, "", "the output directory " + parent.string() + " does not exist");
    }
}

bool driver_keeps_fids(GDALDriver& driver)
{
    const std::string name = driver.GetDescription();
    // GeoJSONSeq writes the FID as each feature's "id" member, as GeoJSON does.
    return name == "GPKG" || name == "SQLite" || name == "GeoJSON" || name == "GeoJSONSeq";
}

} // namespace trisnap
