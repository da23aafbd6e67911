// Matching features by key, and what matching says: missing, extra, attribute mismatches.
#include "assess/measures.hpp"

#include <unordered_map>

namespace trisnap::assess {
namespace {

/// Key -> feature indexes in layer order: the k-th input feature with a key matches the k-th
/// output feature with that key (FIDs are unique, so this only matters for --key).
std::unordered_map<std::string, std::vector<std::uint32_t>> index_keys(const LayerData& d)
{
    std::unordered_map<std::string, std::vector<std::uint32_t>> keys;
    keys.reserve(d.features.size());
    for (std::uint32_t i = 0; i < d.features.size(); ++i) keys[d.features[i].key].push_back(i);
    return keys;
}

std::string shown(const std::string& value) { return value == "\x01null" ? "null" : "'" + value + "'"; }

void compare_values(const LayerData& a, const Feature& fa, const Feature& fb, AssessReport& r)
{
    for (std::size_t i = 0; i < fa.values.size(); ++i) {
        if (fa.values[i] == fb.values[i]) continue;
        ++r.n_attr_mismatch;
        const Pt p = a.anchor(fa);
        r.attr_mismatch.push_back({fa.fid, fb.fid, p.x, p.y, 0, 0, 0,
                                   a.compared_fields[i] + ": " + shown(fa.values[i]) + " vs " + shown(fb.values[i]), {}});
        return; // one mismatch per feature pair
    }
}

} // namespace

Matching measure_matching(const LayerData& a, const LayerData& b, AssessReport& r, std::size_t k)
{
    Matching match(a.features.size(), -1);
    std::vector<bool> matched_b(b.features.size(), false);
    const auto keys_b = index_keys(b);
    std::unordered_map<std::string, std::size_t> used;
    for (std::size_t i = 0; i < a.features.size(); ++i) {
        const Feature& fa = a.features[i];
        const auto it = keys_b.find(fa.key);
        std::size_t& n = used[fa.key];
        if (it != keys_b.end() && n < it->second.size()) {
            const std::uint32_t j = it->second[n++];
            match[i] = j;
            matched_b[j] = true;
            ++r.n_matched;
            compare_values(a, fa, b.features[j], r);
        }
        const bool lost = match[i] < 0 || b.features[static_cast<std::size_t>(match[i])].kind == FeatureKind::empty;
        if (fa.kind != FeatureKind::empty && lost) {
            ++r.n_missing;
            const Pt p = a.anchor(fa);
            r.missing.push_back({fa.fid, match[i] < 0 ? -1 : b.features[static_cast<std::size_t>(match[i])].fid, p.x, p.y,
                                 0, 0, 0, match[i] < 0 ? "no output feature" : "output geometry empty", {}});
        }
    }
    for (std::size_t j = 0; j < b.features.size(); ++j) {
        if (matched_b[j]) continue;
        ++r.n_extra;
        const Pt p = b.anchor(b.features[j]);
        r.extra.push_back({-1, b.features[j].fid, p.x, p.y, 0, 0, 0, "key " + b.features[j].key, {}});
    }
    keep_first(r.missing, k, by_fids);
    keep_first(r.extra, k, by_fids);
    keep_first(r.attr_mismatch, k, by_fids);
    return match;
}

} // namespace trisnap::assess
