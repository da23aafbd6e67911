#pragma once
// Pairs of polygon features of one layer, shared by the overlap and gap measures: candidate
// pairs from an STR tree over feature boxes, the exact boundary test and GEOS's area.
#include "assess/layer_data.hpp"
#include "assess/str_tree.hpp"

#include <tbb/parallel_for.h>

#include <cstdint>
#include <vector>

namespace trisnap::assess {

struct PolygonIndex {
    std::vector<std::uint32_t> ids; // feature indexes
    StrTree tree;                   // over their boxes, item k = ids[k]
};

/// The polygon features of `d` among `candidates` (all of them when empty), indexed by box.
PolygonIndex index_polygons(const LayerData& d, const std::vector<std::uint32_t>& candidates = {});

/// Calls fn(i, j) for pairs i, j (feature indexes, ids order k < m) whose boxes meet (with
/// `positive_area`: overlap with positive area), in parallel.
template <class Fn>
void for_candidate_pairs(const PolygonIndex& index, bool positive_area, Fn&& fn)
{
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, index.ids.size(), 16), [&](const auto& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const Box& box = index.tree.box(static_cast<std::uint32_t>(k));
            index.tree.query(box, [&](std::uint32_t m) {
                if (m <= k || (positive_area && !box.overlaps(index.tree.box(m)))) {
                    return;
                }
                fn(index.ids[k], index.ids[m]);
            });
        }
    });
}

/// Area of the intersection of two polygon features through OGR (GEOS), and its centroid; the same
/// for (a, b) and (b, a): GEOS gets the lower FID first.
double intersection_area(const LayerData& d, const Feature& fa, const Feature& fb, Pt* where);

/// The intersection area of polygon features i and j: 0 at once when the exact boundary test
/// says their interiors are disjoint (valid polygons only), else GEOS's area.
double overlap_area(const LayerData& d, const std::vector<std::int8_t>& interior_left,
                    const std::vector<std::uint8_t>& invalid, std::uint32_t i, std::uint32_t j, Pt* where);

/// Whether the interiors of polygon features i and j meet: the exact boundary test when it can
/// decide (valid polygons), else GEOS's intersection area > 0.
bool interiors_overlap(const LayerData& d, const std::vector<std::int8_t>& interior_left,
                       const std::vector<std::uint8_t>& invalid, std::uint32_t i, std::uint32_t j);

} // namespace trisnap::assess
