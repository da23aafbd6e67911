// assess_layers: read both layers, match, then run each family of measures.
#include "assess/assess.hpp"
#include "assess/measures.hpp"

#include <ogrsf_frmts.h>

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace trisnap {
namespace {

std::vector<std::string> field_names(OGRLayer& layer)
{
    std::vector<std::string> names;
    OGRFeatureDefn* defn = layer.GetLayerDefn();
    for (int i = 0; i < defn->GetFieldCount(); ++i) names.push_back(defn->GetFieldDefn(i)->GetNameRef());
    return names;
}

/// Fields present in both layers, in the original's order (names compared case-insensitively,
/// as OGR does).
std::vector<std::string> common_fields(OGRLayer& a, OGRLayer& b)
{
    std::vector<std::string> common;
    for (const std::string& name : field_names(a))
        if (b.GetLayerDefn()->GetFieldIndex(name.c_str()) >= 0) common.push_back(name);
    return common;
}

void check_key(OGRLayer& layer, const std::string& key)
{
    if (key.empty() || layer.GetLayerDefn()->GetFieldIndex(key.c_str()) >= 0) return;
    std::string fields;
    for (const std::string& name : field_names(layer)) fields += (fields.empty() ? "" : ", ") + name;
    throw std::invalid_argument(fmt::format("--key: layer '{}' has no field '{}'; fields: {}", layer.GetName(), key,
                                            fields.empty() ? "none" : fields));
}

/// The key of the snapped layer: --key, else its `orig_fid` field when the original has none
/// (trisnap writes the input FID there for formats that renumber features: Shapefile, FlatGeobuf),
/// else the FID (empty).
std::string snapped_key(OGRLayer& original, OGRLayer& snapped, const std::string& key)
{
    if (!key.empty()) return key;
    const bool has_orig = snapped.GetLayerDefn()->GetFieldIndex("orig_fid") >= 0;
    return has_orig && original.GetLayerDefn()->GetFieldIndex("orig_fid") < 0 ? "orig_fid" : "";
}

} // namespace

AssessReport assess_layers(OGRLayer& original, OGRLayer& snapped, const AssessOptions& options)
{
    if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
        throw std::invalid_argument(fmt::format("--tolerance must be finite and > 0, got {}", options.tolerance));
    check_key(original, options.key_field);
    check_key(snapped, options.key_field);
    const auto start = std::chrono::steady_clock::now();
    AssessReport r;
    auto last = start;
    const auto phase = [&](const char* name) {
        const auto now = std::chrono::steady_clock::now();
        r.timings.emplace_back(name, std::chrono::duration<double>(now - last).count());
        last = now;
    };
    const std::vector<std::string> fields = common_fields(original, snapped);
    const std::string key_b = snapped_key(original, snapped, options.key_field);
    const assess::LayerData a = assess::read_layer(original, options.key_field, fields);
    const assess::LayerData b = assess::read_layer(snapped, key_b, fields);
    phase("read");
    r.matched_by = !options.key_field.empty() ? "key " + options.key_field : key_b.empty() ? "fid" : "orig_fid";
    r.layer_a = a.name;
    r.layer_b = b.name;
    r.tolerance = options.tolerance;
    r.n_in = static_cast<std::int64_t>(a.features.size());
    r.n_out = static_cast<std::int64_t>(b.features.size());
    const std::size_t k = options.max_examples;
    const assess::Matching match = assess::measure_matching(a, b, r, k);
    phase("matching");
    const std::vector<std::uint8_t> invalid = assess::measure_validity(a, b, r, k);
    phase("validity");
    assess::measure_separations(b, r, k);
    phase("separations");
    assess::measure_overlaps(a, b, match, invalid, r, k);
    phase("overlaps");
    assess::measure_gaps(a, b, match, options.tolerance, r, k);
    phase("gaps");
    assess::measure_hausdorff(a, b, match, options.tolerance, r, k);
    phase("hausdorff");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

bool AssessReport::contract_holds() const { return contract_failures().empty(); }

std::vector<std::string> AssessReport::contract_failures() const
{
    std::vector<std::string> failures;
    const auto count = [&](std::int64_t n, const char* what) {
        if (n > 0) failures.push_back(fmt::format("{} {}", n, what));
    };
    count(n_invalid, "invalid");
    count(n_crossings, "crossings");
    count(n_overlaps, "overlaps");
    count(gaps_new, "new gaps");
    count(n_missing, "missing");
    const double t = tolerance;
    if (min_vertex_vertex && *min_vertex_vertex < t)
        failures.push_back(fmt::format("min_vertex_vertex {:.3g} T < T", *min_vertex_vertex / t));
    if (min_vertex_edge && *min_vertex_edge < t / 2)
        failures.push_back(fmt::format("min_vertex_edge {:.3g} T < T/2", *min_vertex_edge / t));
    if (max_hausdorff > 2 * t) failures.push_back(fmt::format("max_hausdorff {:.3g} T > 2T", max_hausdorff / t));
    return failures;
}

} // namespace trisnap
