#include "io/file_safety.hpp"

#include "config/errors.hpp"

#include <cpl_string.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sys/stat.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

/// realpath(3), or "" when the path does not resolve.
std::string real_path(const fs::path& path)
{
    char buffer[PATH_MAX];
    if (::realpath(path.c_str(), buffer) == nullptr) {
        return "";
    }
    return buffer;
}

/// Where a path that does not exist would be: its directory resolved, joined with its name.
std::string would_be_path(const fs::path& path)
{
    const fs::path absolute = fs::absolute(path).lexically_normal();
    const std::string parent = real_path(absolute.parent_path());
    if (parent.empty()) {
        return absolute.string();
    }
    return (fs::path(parent) / absolute.filename()).string();
}

/// Companion files as extensions that replace OUT's own, per driver.
const std::map<std::string, std::vector<std::string>>& companion_extensions()
{
    static const std::map<std::string, std::vector<std::string>> table = {
        {"ESRI Shapefile", {"shp", "shx", "dbf", "prj", "cpg", "qix", "sbn", "sbx", "qpj"}},
        {"GML", {"xsd", "gfs"}},
        {"MapInfo File", {"tab", "dat", "map", "id", "ind", "mif", "mid"}},
    };
    return table;
}

/// Companion files as suffixes appended to OUT (SQLite's journals).
const std::map<std::string, std::vector<std::string>>& companion_suffixes()
{
    static const std::map<std::string, std::vector<std::string>> table = {
        {"GPKG", {"-journal", "-wal", "-shm"}},
        {"SQLite", {"-journal", "-wal", "-shm"}},
    };
    return table;
}

std::string upper(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
    return s;
}

void add_replaced_extensions(const fs::path& path, const std::vector<std::string>& extensions,
                             std::vector<std::string>& out)
{
    for (const std::string& ext : extensions) {
        fs::path lower_case = path;
        fs::path upper_case = path;
        out.push_back(lower_case.replace_extension(ext).string());
        out.push_back(upper_case.replace_extension(upper(ext)).string());
    }
}

} // namespace

bool FileIdentity::same_file(const FileIdentity& other) const
{
    if (exists && other.exists) {
        return device == other.device && inode == other.inode;
    }
    return real_path == other.real_path;
}

FileIdentity identify_file(const std::string& path)
{
    FileIdentity id;
    struct stat info{};
    id.exists = ::stat(path.c_str(), &info) == 0;
    if (id.exists) {
        id.device = info.st_dev;
        id.inode = info.st_ino;
    }
    id.real_path = id.exists ? real_path(path) : would_be_path(path);
    return id;
}

void ProtectedFiles::add_file(const std::string& path, const std::string& label)
{
    if (path.empty() || path.rfind("/vsi", 0) == 0) {
        return; // a virtual path (e.g. /vsizip/...) names no local file of its own
    }
    m_files.push_back(Entry{identify_file(path), path, label});
}

void ProtectedFiles::add_dataset(GDALDataset& dataset, const std::string& label)
{
    const CPLStringList files(dataset.GetFileList());
    for (int i = 0; i < files.size(); ++i) {
        add_file(files[i], label);
    }
    add_file(dataset.GetDescription(), label); // OSM and some others list nothing
}

const ProtectedFiles::Entry* ProtectedFiles::find(const std::string& path) const
{
    const FileIdentity id = identify_file(path);
    for (const Entry& entry : m_files) {
        if (entry.identity.same_file(id)) {
            return &entry;
        }
    }
    return nullptr;
}

std::string ProtectedFiles::owner_of(const std::string& path) const
{
    const Entry* entry = find(path);
    return entry ? entry->label : "";
}

void ProtectedFiles::refuse(const std::string& path, const std::string& what) const
{
    const Entry* entry = find(path);
    if (entry == nullptr) {
        return;
    }
    const std::string same = entry->path == path ? "" : " (the same file as " + entry->path + ")";
    throw argument_error(what + " " + path + ": is a file of " + entry->label + same + "; choose another path");
}

void ProtectedFiles::refuse_tree(const std::string& directory, const std::string& what) const
{
    refuse(directory, what);
    const std::string root = identify_file(directory).real_path + "/";
    for (const Entry& entry : m_files) {
        if (entry.identity.real_path.compare(0, root.size(), root) == 0) {
            throw argument_error(what + " " + directory + ": holds " + entry.path + ", a file of " + entry.label +
                                 "; choose another directory");
        }
    }
}

std::vector<std::string> dataset_files_for(const std::string& path, GDALDriver& driver)
{
    std::vector<std::string> files{path};
    const std::string name = driver.GetDescription();
    if (auto it = companion_extensions().find(name); it != companion_extensions().end()) {
        add_replaced_extensions(fs::path(path), it->second, files);
    }
    if (auto it = companion_suffixes().find(name); it != companion_suffixes().end()) {
        for (const std::string& suffix : it->second) {
            files.push_back(path + suffix);
        }
    }
    return files;
}

} // namespace trisnap
