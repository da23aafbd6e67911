#pragma once
// The measures of assess_layers, one function per family; each fills its part of the report.
#include "assess/assess.hpp"
#include "assess/layer_data.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace trisnap::assess {

/// Input feature index -> output feature index, or -1.
using Matching = std::vector<std::int64_t>;

Matching measure_matching(const LayerData& a, const LayerData& b, AssessReport& report, std::size_t k);
/// Returns, per output feature, 1 when it is an invalid polygon.
std::vector<std::uint8_t> measure_validity(const LayerData& a, const LayerData& b, AssessReport& report, std::size_t k);
void measure_separations(const LayerData& b, AssessReport& report, std::size_t k);
/// Overlapping output pairs, and which of them overlapped in the input too (`text` "in input").
void measure_overlaps(const LayerData& a, const LayerData& b, const Matching& match,
                      const std::vector<std::uint8_t>& invalid, AssessReport& report, std::size_t k);
void measure_gaps(const LayerData& a, const LayerData& b, const Matching& match, double tolerance,
                  AssessReport& report, std::size_t k);
void measure_hausdorff(const LayerData& a, const LayerData& b, const Matching& match, double tolerance,
                       AssessReport& report, std::size_t k);

/// Sorts examples with `less` and keeps the first k: deterministic whatever the thread count.
template <class Less>
void keep_first(std::vector<AssessExample>& examples, std::size_t k, Less less)
{
    std::sort(examples.begin(), examples.end(), less);
    if (examples.size() > k) examples.resize(k);
}

/// Order by (fid_a, fid_b, x, y): for defect lists.
inline bool by_fids(const AssessExample& a, const AssessExample& b)
{
    if (a.fid_a != b.fid_a) return a.fid_a < b.fid_a;
    if (a.fid_b != b.fid_b) return a.fid_b < b.fid_b;
    if (a.x != b.x) return a.x < b.x;
    return a.y < b.y;
}

/// Order by value then fids: for "smallest" lists.
inline bool by_value(const AssessExample& a, const AssessExample& b)
{
    if (a.value != b.value) return a.value < b.value;
    return by_fids(a, b);
}

/// Order by decreasing value then fids: for "largest" lists.
inline bool by_value_desc(const AssessExample& a, const AssessExample& b)
{
    if (a.value != b.value) return a.value > b.value;
    return by_fids(a, b);
}

} // namespace trisnap::assess
