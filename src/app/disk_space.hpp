#pragma once
// Room for the work files of an out-of-core run, checked twice: before the read (from the
// input's size, so that a disk far too small is refused before anything is spooled) and after
// it (from features.bin, which the rest of the work files follow). Both say which directory
// and how much, in one line; a disk that fills up anyway is tiling::disk_full_error, which
// main() phrases the same way (app/exit_status.hpp).
#include "app/plan.hpp"
#include "app/work_dir.hpp"
#include "stitch/spool.hpp"

#include <cstdint>

namespace trisnap {

/// Bytes free for the work files: the file system's (statvfs), or TRISNAP_TEST_FREE_DISK
/// (bytes) when that is set: the tests' small disk (mounting a small file system needs root).
std::uint64_t free_disk(const tiling::WorkStore& store);

/// The least the work files of `plan`'s input take, from the size of its files: features.bin at
/// the lowest ratio to the input measured on the shared data sets, the buckets and the tile
/// results as much again each, and a margin. A layer of a file that holds several counts for
/// its share of the file's features.
std::uint64_t work_files_floor(const Plan& plan);

/// Before the read: throws io_error naming the work directory when its disk has less free than
/// work_files_floor().
void check_disk_before_read(WorkDir& work, const Plan& plan);

/// After the read: throws io_error naming the work directory when its disk cannot hold the rest
/// of the work files (about twice features.bin, and a margin).
void check_disk_after_read(WorkDir& work, const stitch::SpoolMeta& meta);

} // namespace trisnap
