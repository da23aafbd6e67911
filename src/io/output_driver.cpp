// Choosing and checking the output format and path (the part of the writer that runs before
// any data is read, so `validate` can use it without writing anything).
#include "io/writer.hpp"

#include "config/errors.hpp"
#include "io/io_error.hpp"

#include <algorithm>
#include <sstream>

namespace trisnap {
namespace {

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool can_create_vector(GDALDriver& driver)
{
    return driver.GetMetadataItem(GDAL_DCAP_VECTOR) && driver.GetMetadataItem(GDAL_DCAP_CREATE);
}

bool lists_extension(GDALDriver& driver, const std::string& ext)
{
    const char* list = driver.GetMetadataItem(GDAL_DMD_EXTENSIONS);
    std::istringstream words(list ? list : "");
    for (std::string word; words >> word;)
        if (lower(word) == ext) return true;
    return false;
}

GDALDriver* driver_for_extension(const std::string& ext)
{
    GDALDriverManager* manager = GetGDALDriverManager();
    for (int i = 0; i < manager->GetDriverCount(); ++i) {
        GDALDriver* driver = manager->GetDriver(i);
        if (can_create_vector(*driver) && lists_extension(*driver, ext)) return driver;
    }
    return nullptr;
}

/// trisnap writes files (through its checking file system): a driver without GDAL's virtual
/// I/O writes to memory, a database or a web service, where nothing could be checked or renamed.
void refuse_non_file_driver(GDALDriver& driver, const std::string& what)
{
    if (driver.GetMetadataItem(GDAL_DCAP_VIRTUALIO) == nullptr) {
        throw argument_error(what + ": the " + std::string(driver.GetDescription()) +
                             " format writes no file (memory, a database or a service); trisnap writes files, "
                             "e.g. -f GPKG, FlatGeobuf, \"ESRI Shapefile\", GeoJSON");
    }
}

GDALDriver& driver_by_name(const std::string& format)
{
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(format.c_str());
    if (!driver) {
        throw argument_error("-f " + format + ": unknown GDAL format");
    }
    if (!can_create_vector(*driver)) {
        throw argument_error("-f " + format + ": this format cannot be written");
    }
    refuse_non_file_driver(*driver, "-f " + format);
    return *driver;
}

} // namespace

GDALDriver& output_driver(const std::string& path, const std::string& format)
{
    if (!format.empty()) {
        return driver_by_name(format);
    }
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    GDALDriver* driver = ext.size() > 1 ? driver_for_extension(ext.substr(1)) : nullptr;
    if (!driver) {
        throw argument_error(path + ": cannot tell the output format from the extension '" + ext +
                             "'; give one with -f (e.g. -f GPKG)");
    }
    refuse_non_file_driver(*driver, path);
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
    const fs::path target(options.path);
    std::error_code ec;
    if (fs::exists(input_path, ec) && fs::exists(target, ec) && fs::equivalent(input_path, target, ec)) {
        throw argument_error(options.path + ": output is the input; choose another OUT");
    }
    if (fs::exists(target, ec) && !options.overwrite) {
        throw argument_error(options.path + ": already exists; add --overwrite to replace it");
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
    return name == "GPKG" || name == "SQLite" || name == "GeoJSON";
}

} // namespace trisnap
