#pragma once
// The measures of assess_data, one function per family; each fills its part of the report.
#include "assess/assess.hpp"
#include "assess/excuses.hpp"
#include "assess/layer_data.hpp"

#include <algorithm>
#include <cstdint>
#include <tuple>
#include <vector>

namespace trisnap::assess {

/// Input feature index -> output feature index, or -1.
using Matching = std::vector<std::int64_t>;

/// What every measure needs: both layers, how they match, T, the example cap and the excuses.
struct Context {
    const LayerData& a;
    const LayerData& b;
    Matching match;                     // input index -> output index, or -1
    std::vector<std::int64_t> input_of; // output index -> input index, or -1
    double tolerance = 0;
    std::size_t k = 20;
    Excuses excuses;
};

/// Matches features and fills missing (with excuses), extra and attribute mismatches.
Matching measure_matching(const LayerData& a, const LayerData& b, const Excuses& excuses, AssessReport& report,
                          std::size_t k);
/// Returns, per feature of `d`, 1 when it is an invalid polygon (GDAL's IsValid), checking only
/// the features in `only` (every one when null); fills the report's invalid list when `report`
/// is given (the output), else only answers (the input).
std::vector<std::uint8_t> invalid_polygons(const LayerData& d, const std::vector<std::uint32_t>* only, AssessReport* report,
                                           std::size_t k);
/// Areas, empty and unmeasurable outputs, and invalid polygons of the output.
std::vector<std::uint8_t> measure_validity(const Context& c, AssessReport& report);
void measure_separations(const Context& c, AssessReport& report);
/// Overlapping output pairs, and which of them overlapped in the input too.
void measure_overlaps(const Context& c, const std::vector<std::uint8_t>& invalid, AssessReport& report);
void measure_gaps(const Context& c, AssessReport& report);
void measure_hausdorff(const Context& c, AssessReport& report);
/// The report's worst sites (AssessReport::worst) from its examples.
void measure_worst(const Context& c, std::size_t n, AssessReport& report);

/// An example of a feature, or a pair of features, at a place.
inline AssessExample example_at(std::int64_t fid_a, std::int64_t fid_b, Pt at, double value = 0, std::string text = {})
{
    AssessExample e;
    e.fid_a = fid_a;
    e.fid_b = fid_b;
    e.x = at.x;
    e.y = at.y;
    e.value = value;
    e.text = std::move(text);
    return e;
}

/// An example with two places: a vertex and its partner (other vertex, closest point).
inline AssessExample pair_example(std::int64_t fid_a, std::int64_t fid_b, Pt p, Pt q, double value, std::string text = {})
{
    AssessExample e = example_at(fid_a, fid_b, p, value, std::move(text));
    e.x2 = q.x;
    e.y2 = q.y;
    return e;
}

/// Sorts examples with `less` and keeps the first k: deterministic whatever the thread count.
template <class Less>
void keep_first(std::vector<AssessExample>& examples, std::size_t k, Less less)
{
    std::sort(examples.begin(), examples.end(), less);
    if (examples.size() > k) {
        examples.resize(k);
    }
}

/// Order by (fid_a, fid_b, x, y): for defect lists.
inline bool by_fids(const AssessExample& a, const AssessExample& b)
{
    return std::tie(a.fid_a, a.fid_b, a.x, a.y) < std::tie(b.fid_a, b.fid_b, b.x, b.y);
}

/// New defects first, then by FIDs: for overlaps and crossings, some of which the input had.
inline bool new_first(const AssessExample& a, const AssessExample& b)
{
    if (a.is_new != b.is_new) {
        return a.is_new;
    }
    return by_fids(a, b);
}

/// Order by value then fids: for "smallest" lists.
inline bool by_value(const AssessExample& a, const AssessExample& b)
{
    if (a.value != b.value) {
        return a.value < b.value;
    }
    return by_fids(a, b);
}

/// Order by decreasing value then fids: for "largest" lists.
inline bool by_value_desc(const AssessExample& a, const AssessExample& b)
{
    if (a.value != b.value) {
        return a.value > b.value;
    }
    return by_fids(a, b);
}

/// Notes an excused defect in the report's list.
void note_excused(AssessReport& report, const AssessExample& defect, const std::string& what);

} // namespace trisnap::assess
