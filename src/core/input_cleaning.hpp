#pragma once
// Turns caller geometry into clean rings and lines for the triangulation, and reports every
// repair: unclosed rings are closed, consecutive duplicates dropped, degenerate rings and lines
// dropped, features with non-finite or unusably large coordinates rejected. Nothing is dropped
// without a Problem naming the feature.
#include "core/geometry.hpp"
#include "core/problems.hpp"

#include <cstdint>
#include <vector>

namespace trisnap::detail {

struct CleanRing {
    std::vector<Coord> points; ///< open: no closing point; >= 3 distinct consecutive points
    std::uint32_t polygon = 0; ///< index of the polygon (part) in the feature
    bool hole = false;
};

struct CleanFeature {
    std::size_t index = 0; ///< position in the caller's vector
    std::int64_t id = 0;
    bool polygonal = false;
    bool rejected = false; ///< nothing of it goes into the triangulation
    std::vector<CleanRing> rings;
    std::vector<std::vector<Coord>> lines; ///< >= 2 distinct consecutive points each
    std::size_t shells = 0;                ///< kept polygon parts
    std::size_t holes = 0;                 ///< kept holes
};

/// Cleans one feature, `id` with geometry `g` (`index`: its position in the caller's sequence);
/// `problems` receives one entry per repair kind.
CleanFeature clean_feature(std::int64_t id, const Geometry& g, std::size_t index, double tolerance,
                           std::vector<Problem>& problems);

/// Cuts every ring and line of every feature to its first point; counts and flags stay. What
/// the engine keeps of a feature once the triangulation's records hold its points (Mesh), and
/// what stitch/ reads back from its spool as an outline. The outlines are new allocations and
/// the cleaned features are freed whole after them: cut one ring at a time, the rings' memory
/// came back as a quarter of a million holes between the features' live ring tables, too small
/// for anything the build allocates (Andorra x43 untiled: 38 MiB more heap at the peak).
void cut_to_outlines(std::vector<CleanFeature>& features);

/// Cleans every feature, one CleanFeature per input feature in their order (`index` its position);
/// `problems` receives one entry per repair kind per feature.
std::vector<CleanFeature> clean_input(const std::vector<Feature>& features, double tolerance,
                                      std::vector<Problem>& problems);

} // namespace trisnap::detail
