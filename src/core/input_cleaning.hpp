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

/// What the engine keeps of a cleaned feature once the mesh's records hold its points (Mesh's
/// outlining constructor), and what its problems need: ids, flags, counts and where to place
/// them. 56 bytes and no allocation: the features cut to their first points as CleanFeatures
/// kept 88 bytes and two allocations a ring (Andorra x43 untiled: 35.8 MB at the peak).
struct Outline {
    std::size_t index = 0;        ///< position in the caller's vector
    std::int64_t id = 0;
    std::uint32_t paths = 0;      ///< its rings, or its lines
    std::uint32_t parts = 0;      ///< kept polygon parts (shells), or its lines
    std::uint32_t holes = 0;      ///< kept holes
    std::uint32_t first_line = 0; ///< its lines' first points start here in Outlines::line_starts
    double x = 0, y = 0;          ///< its first point (first ring's or line's): where its problems are
    bool polygonal = false;
    bool rejected = false;        ///< nothing of it went into the triangulation
};
static_assert(sizeof(Outline) <= 56, "Outline is one per feature for the whole run: keep it small");

struct Outlines {
    std::vector<Outline> features; ///< one per cleaned feature, in their order
    std::vector<Coord> line_starts; ///< each line's first point, feature after feature
    std::size_t size() const { return features.size(); }
    const Outline& operator[](std::size_t f) const { return features[f]; }
    /// Feature f's lines' first points (none for a polygon).
    std::vector<Coord> starts(std::size_t f) const
    {
        const Outline& o = features[f];
        if (o.polygonal) return {};
        return {line_starts.begin() + o.first_line, line_starts.begin() + o.first_line + o.parts};
    }
};

/// One feature's outline (first_line 0: its lines' first points are not kept). Throws
/// std::length_error when a count does not fit 32 bits.
Outline outline_of(const CleanFeature& f);
/// Every feature's outline, and their lines' first points.
Outlines make_outlines(const std::vector<CleanFeature>& features);

/// Cleans every feature, one CleanFeature per input feature in their order (`index` its position);
/// `problems` receives one entry per repair kind per feature.
std::vector<CleanFeature> clean_input(const std::vector<Feature>& features, double tolerance,
                                      std::vector<Problem>& problems);

} // namespace trisnap::detail
