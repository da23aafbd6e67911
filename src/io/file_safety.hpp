#pragma once
// "Is this path one of the files we must not touch?" A dataset is often several files (a
// Shapefile's .shp, .shx, .dbf, ...), and one file has many names (symlinks, hard links,
// "./a/../a.gpkg"), so two paths are compared by what they resolve to: the real path and the
// (device, inode) pair. Used for OUT and every file the output driver creates, --report, and
// any work directory, against every file of the input dataset (GDAL's GetFileList()).
#include <gdal_priv.h>

#include <string>
#include <sys/types.h>
#include <vector>

namespace trisnap {

/// A path as the operating system resolves it. For a path that does not exist yet, the real
/// path of its directory joined with its name (the file it would become).
struct FileIdentity {
    std::string real_path;
    bool exists = false;
    dev_t device = 0;
    ino_t inode = 0;

    bool same_file(const FileIdentity& other) const;
};

FileIdentity identify_file(const std::string& path);

/// Files that a run must never write to, remove or rename over, each with a label saying whose
/// file it is ("the input in.gpkg"). Cheap to copy.
class ProtectedFiles {
public:
    /// Adds every file of `dataset` (GetFileList(); its description when the driver lists none).
    void add_dataset(GDALDataset& dataset, const std::string& label);
    void add_file(const std::string& path, const std::string& label);
    /// The label of the protected file `path` is, or "" when it is none of them.
    std::string owner_of(const std::string& path) const;
    /// Throws argument_error "WHAT PATH: is FILE, a file of LABEL; choose another path" when
    /// `path` is one of the protected files. `what` names the option ("OUT", "--report").
    void refuse(const std::string& path, const std::string& what) const;
    /// For a directory that a run fills and then removes (a work directory): throws
    /// argument_error when `directory` is, or holds at any depth, one of the protected files.
    void refuse_tree(const std::string& directory, const std::string& what) const;
    bool empty() const { return m_files.empty(); }

private:
    struct Entry {
        FileIdentity identity;
        std::string path;
        std::string label;
    };
    const Entry* find(const std::string& path) const;
    std::vector<Entry> m_files;
};

/// Every file `driver` may create for the dataset `path`: the path itself, and for multi-file
/// formats its companions (Shapefile .shp .shx .dbf .prj .cpg .qix, GML .xsd .gfs, MapInfo .tab
/// .dat .map .id .ind, SQLite journals ...).
std::vector<std::string> dataset_files_for(const std::string& path, GDALDriver& driver);

} // namespace trisnap
