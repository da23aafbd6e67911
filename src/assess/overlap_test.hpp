#pragma once
// An exact, cheap decision whether the interiors of two valid polygon features meet, from their
// boundaries only, so that neighbours in a coverage need no GEOS overlay. Holds for valid
// polygons whose boundaries meet only at common vertices and identical segments: then the
// interiors meet iff a shared segment has both interiors on the same side, or a segment of one
// that is not shared lies inside the other (its relative interior cannot touch the other's
// boundary, so its midpoint decides). Anything else (crossing or collinear-overlapping edges,
// large windows) is left to GEOS: `unknown`.
#include "assess/layer_data.hpp"

#include <cstdint>
#include <vector>

namespace trisnap::assess {

enum class OverlapVerdict { disjoint, overlap, unknown };

/// Per part: 1 when the feature's interior lies left of the part's edges in stored order.
std::vector<std::int8_t> interior_left_of_parts(const LayerData& d);

OverlapVerdict interiors_meet(const LayerData& d, const std::vector<std::int8_t>& interior_left, const Feature& fa,
                              const Feature& fb);

} // namespace trisnap::assess
