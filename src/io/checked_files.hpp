#pragma once
// Checked writes for GDAL drivers that do not check their own. Several drivers (GeoJSON,
// GeoJSONSeq, GML, KML, CSV) ignore the result of VSIFWriteL and VSIFCloseL, so a full disk
// leaves a file cut short and the driver reports success. Paths under checked_path() go through
// a GDAL virtual file system that forwards every call to the local file system and remembers
// the first write, flush, truncate or close that failed for each file; the writer asks for it
// with take_write_failure() before it trusts the result. Every 8 MiB written to a file it also
// asks the kernel to start writing them to disk (sync_file_range), so that the fsync before OUT
// goes into place has little left to wait for.
#include <filesystem>
#include <string>

namespace trisnap {

/// The same file seen through the checking file system ("/vsitrisnap_checked" + absolute path).
/// Installs the file system on first use; safe from any thread.
std::string checked_path(const std::filesystem::path& path);

/// "FILE: reason" (FILE relative to `directory`) for the first failed write, flush, truncate or
/// close of a file under `directory` since the last call, or "" when every one succeeded.
/// Forgets what it returns and everything else recorded under `directory`. Free when nothing
/// failed anywhere, so it can be asked after every feature.
std::string take_write_failure(const std::filesystem::path& directory);

} // namespace trisnap
