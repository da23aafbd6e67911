#pragma once
// Labels every face with the set of polygon features it lies in (prepair's method): a flood
// fill from the outside across all edges; crossing a constrained edge toggles membership of each
// feature that owns an odd number of the input edges through it (odd-even rule per feature, so
// self-intersecting or overlapping input rings are repaired the way OGC validity expects).
// A face may belong to several features where input polygons overlap.
#include "core/mesh.hpp"

#include <vector>

namespace trisnap::detail {

struct FaceLabels {
    std::vector<std::vector<std::uint32_t>> sets;             ///< label id -> sorted feature indices
    std::vector<std::vector<cdt::Face_handle>> faces_of;      ///< feature index -> its faces
};

FaceLabels label_faces(Mesh& mesh, std::size_t feature_count);

} // namespace trisnap::detail
