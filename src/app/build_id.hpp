#pragma once
// Which build of trisnap this is, beyond its version: the steps of a cluster run (plan,
// snap-tiles, stitch) must all run the same build, since a change to the engine between two
// builds of one version can change a tile's bytes and the seams then disagree.
#include <string>

namespace trisnap {

/// "VERSION+g<commit>" (a git checkout, ".dirty-<hash of the diff>" appended when tracked files
/// differ from the commit), else "VERSION+c<hash>" of this file's compile date and time and the
/// compiler (a build without git). Two builds of one commit and diff share an id; so do two
/// copies of one binary.
const std::string& build_id();

} // namespace trisnap
