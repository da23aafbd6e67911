// Matching features by key, and what matching says: missing, extra, attribute mismatches.
#include "assess/measures.hpp"

#include <algorithm>

namespace trisnap::assess {
namespace {

/// Feature indexes ordered by key, layer order among equal keys.
std::vector<std::uint32_t> order_by_key(const LayerData& d)
{
    std::vector<std::uint32_t> order(d.features.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) {
        order[i] = i;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t x, std::uint32_t y) { return d.features[x].key < d.features[y].key; });
    return order;
}

/// The k-th input feature with a key matches the k-th output feature with that key (FIDs are
/// unique, so this only matters for --key). A merge of the two key orders: no hash maps.
Matching match_keys(const LayerData& a, const LayerData& b)
{
    Matching match(a.features.size(), -1);
    const std::vector<std::uint32_t> oa = order_by_key(a), ob = order_by_key(b);
    for (std::size_t ia = 0, ib = 0; ia < oa.size() && ib < ob.size();) {
        const std::string& ka = a.features[oa[ia]].key;
        const std::string& kb = b.features[ob[ib]].key;
        if (ka < kb) {
            ++ia;
        } else if (kb < ka) {
            ++ib;
        } else {
            match[oa[ia++]] = ob[ib++];
        }
    }
    return match;
}

std::string shown(const std::string& value) { return value == "\x01null" ? "null" : "'" + value + "'"; }

void compare_values(const LayerData& a, const Feature& fa, const Feature& fb, AssessReport& r)
{
    for (std::size_t i = 0; i < fa.values.size(); ++i) {
        if (fa.values[i] == fb.values[i]) {
            continue;
        }
        ++r.n_attr_mismatch;
        const Pt p = a.anchor(fa);
        const std::string difference = a.compared_fields[i] + ": " + shown(fa.values[i]) + " vs " + shown(fb.values[i]);
        r.attr_mismatch.push_back(example_at(fa.fid, fb.fid, p, 0, difference));
        return; // one mismatch per feature pair
    }
}

} // namespace

void note_excused(AssessReport& r, const AssessExample& defect, const std::string& what)
{
    AssessExample e = defect;
    e.text = what;
    r.excused.push_back(std::move(e));
}

namespace {

/// A lost input feature: where, how big (mean width 2A/P, or length for lines), and its box.
AssessExample lost_feature(const LayerData& a, const Feature& fa, std::int64_t fid_out, const char* reason)
{
    const Pt p = fa.box.centre();
    const double length = a.length(fa);
    AssessExample e = example_at(fa.fid, fid_out, p, 0, reason);
    e.edge = {fa.box.xmin, fa.box.ymin, fa.box.xmax, fa.box.ymax};
    e.value = fa.kind == FeatureKind::polygon ? (length > 0 ? 2 * a.area(fa) / length : 0.0) : length;
    return e;
}

void note_missing(const LayerData& a, const LayerData& b, const Excuses& excuses, std::size_t i, std::int64_t j,
                  AssessReport& r)
{
    const Feature& fa = a.features[i];
    const std::int64_t fid_out = j < 0 ? -1 : b.features[static_cast<std::size_t>(j)].fid;
    AssessExample e = lost_feature(a, fa, fid_out, j < 0 ? "no output feature" : "output geometry empty");
    ++r.n_missing;
    e.excused_by = excuses.explain(Defect::missing, fa.fid);
    if (!e.excused_by.empty()) {
        ++r.excused_counts.missing;
        note_excused(r, e, "missing");
    }
    r.missing.push_back(std::move(e));
}

} // namespace

Matching measure_matching(const LayerData& a, const LayerData& b, const Excuses& excuses, AssessReport& r, std::size_t k)
{
    const Matching match = match_keys(a, b);
    std::vector<bool> matched_b(b.features.size(), false);
    for (std::size_t i = 0; i < a.features.size(); ++i) {
        const Feature& fa = a.features[i];
        const std::int64_t j = match[i];
        if (j >= 0) {
            matched_b[static_cast<std::size_t>(j)] = true;
            ++r.n_matched;
            compare_values(a, fa, b.features[static_cast<std::size_t>(j)], r);
        }
        const bool lost = j < 0 || b.features[static_cast<std::size_t>(j)].kind == FeatureKind::empty;
        const bool measurable = fa.kind == FeatureKind::line || fa.kind == FeatureKind::polygon;
        if (measurable && lost) {
            note_missing(a, b, excuses, i, j, r);
        }
    }
    for (std::size_t j = 0; j < b.features.size(); ++j) {
        if (matched_b[j]) {
            continue;
        }
        ++r.n_extra;
        const Pt p = b.anchor(b.features[j]);
        r.extra.push_back(example_at(-1, b.features[j].fid, p, 0, "key " + b.features[j].key));
    }
    keep_first(r.missing, k, by_fids);
    keep_first(r.extra, k, by_fids);
    keep_first(r.attr_mismatch, k, by_fids);
    return match;
}

} // namespace trisnap::assess
