#pragma once
// The output's distinct vertices and distinct segments (a boundary shared by two features is
// one set of segments, not two), with the features that own them, and helpers the separation
// and crossing measures share.
#include "assess/layer_data.hpp"
#include "assess/measures.hpp"
#include "assess/str_tree.hpp"

#include <tbb/combinable.h>

#include <cstdint>
#include <vector>

namespace trisnap::assess {

struct Owned {
    Pt p;
    std::uint32_t feature; // the first feature (lowest index) that has it
};

struct Segment {
    Pt a, b;                    // a < b
    std::uint32_t feature;      // the first feature that has it
    std::uint32_t owners_begin; // owners[owners_begin, owners_end): every feature that has it
    std::uint32_t owners_end;
};

struct DistinctSegments {
    std::vector<Segment> segments;
    std::vector<std::uint32_t> owners;
    StrTree tree; // over the segments' boxes
};

std::vector<Owned> distinct_vertices(const LayerData& d);
/// The distinct segments of the features of `d` (of those with keep[f] != 0 when given).
DistinctSegments distinct_segments(const LayerData& d, const std::vector<std::uint8_t>* keep = nullptr);

using Examples = tbb::combinable<std::vector<AssessExample>>;

/// Every thread's examples in one list.
std::vector<AssessExample> gather(Examples& per_thread);

/// Keeps, per thread, only the k best so memory stays bounded on huge layers.
template <class Less>
void push_bounded(std::vector<AssessExample>& v, AssessExample e, std::size_t k, Less less)
{
    v.push_back(std::move(e));
    if (v.size() >= 4 * k + 64) {
        keep_first(v, k, less);
    }
}

/// Crossings of the output, and how many are new (the input features of the two segments did
/// not cross each other, or the one feature did not cross itself, in the input).
void measure_crossings(const Context& c, const DistinctSegments& out, AssessReport& report);

} // namespace trisnap::assess
