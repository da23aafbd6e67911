#pragma once
// Labels every face with the set of polygon features it lies in (prepair's method): a flood
// fill from the outside across all edges; crossing a constrained edge toggles membership of each
// feature that owns an odd number of the input edges through it (odd-even rule per feature, so
// self-intersecting or overlapping input rings are repaired the way OGC validity expects).
// A face may belong to several features where input polygons overlap.
#include "core/mesh.hpp"

#include <span>
#include <vector>

namespace trisnap::detail {

struct FaceLabels {
    /// Label id -> its sorted feature indices, all sets in one array: label l's features are
    /// set_features[set_first[l] .. set_first[l + 1]). (A vector per label: a quarter of a
    /// million small allocations on Andorra x43, each face's lookup a second cache miss.)
    std::vector<std::size_t> set_first{0};
    std::vector<std::uint32_t> set_features;
    std::size_t labels() const { return set_first.size() - 1; }
    std::span<const std::uint32_t> set(std::uint32_t label) const
    {
        return {set_features.data() + set_first[label], set_first[label + 1] - set_first[label]};
    }
    /// Each feature's faces, in the triangulation's face order, features in blocks of
    /// k_block: one exact allocation per block (a vector per feature grew by doubling: a quarter
    /// of a million growing vectors on Andorra x43, in a heap the cleaned input's freed rings
    /// had fragmented), freed block by block as the outputs are made (release_block).
    static constexpr std::size_t k_block = 4096;
    std::vector<std::vector<cdt::Face_handle>> blocks;
    std::vector<std::size_t> first; ///< prefix sums of the faces per feature, over all features
    std::span<const cdt::Face_handle> faces_of(std::size_t feature) const
    {
        const std::size_t base = first[feature / k_block * k_block];
        return {blocks[feature / k_block].data() + (first[feature] - base), first[feature + 1] - first[feature]};
    }
    /// Frees the block of `feature` (its faces and those of the k_block - 1 around it).
    void release_block(std::size_t feature) { std::vector<cdt::Face_handle>().swap(blocks[feature / k_block]); }
};

FaceLabels label_faces(Mesh& mesh, std::size_t feature_count);

} // namespace trisnap::detail
