#pragma once
// Clipping in pixel space, so features far outside a zoomed view cost nothing to write.
#include "render/types.hpp"

#include <vector>

namespace trisnap::render {

/// Sutherland–Hodgman: the part of a closed ring inside `box` as one ring (possibly with edges
/// along the box border; even-odd filling of several clipped rings stays right inside the box).
std::vector<XY> clip_ring(const std::vector<XY>& ring, const Box& box);

/// The pieces of an open polyline inside `box` (Liang–Barsky per segment, joined when consecutive).
std::vector<std::vector<XY>> clip_line(const std::vector<XY>& line, const Box& box);

/// Drops points closer than `min_step` to the last one kept; keeps the first and the last.
std::vector<XY> drop_close_points(const std::vector<XY>& points, double min_step);

} // namespace trisnap::render
