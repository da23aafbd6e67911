#include "assess/layer_pair.hpp"

#include "io/io_error.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <fmt/format.h>

#include <stdexcept>

namespace trisnap::assess {
namespace {

std::vector<std::string> field_names(OGRLayer& layer)
{
    std::vector<std::string> names;
    OGRFeatureDefn* defn = layer.GetLayerDefn();
    for (int i = 0; i < defn->GetFieldCount(); ++i) {
        names.push_back(defn->GetFieldDefn(i)->GetNameRef());
    }
    return names;
}

/// Fields present in both layers, in the original's order (names compared case-insensitively,
/// as OGR does).
std::vector<std::string> common_fields(OGRLayer& a, OGRLayer& b)
{
    std::vector<std::string> common;
    for (const std::string& name : field_names(a)) {
        if (b.GetLayerDefn()->GetFieldIndex(name.c_str()) >= 0) {
            common.push_back(name);
        }
    }
    return common;
}

void check_key(OGRLayer& layer, const std::string& key)
{
    if (key.empty() || layer.GetLayerDefn()->GetFieldIndex(key.c_str()) >= 0) {
        return;
    }
    std::string fields;
    for (const std::string& name : field_names(layer)) {
        fields += (fields.empty() ? "" : ", ") + name;
    }
    throw std::invalid_argument(fmt::format("--key: layer '{}' has no field '{}'; fields: {}", layer.GetName(), key,
                                            fields.empty() ? "none" : fields));
}

/// The key of the snapped layer: --key, else its `orig_fid` field when the original has none
/// (trisnap writes the input FID there for formats that renumber features: Shapefile, FlatGeobuf),
/// else the FID (empty).
std::string snapped_key(OGRLayer& original, OGRLayer& snapped, const std::string& key)
{
    if (!key.empty()) {
        return key;
    }
    const bool has_orig = snapped.GetLayerDefn()->GetFieldIndex("orig_fid") >= 0;
    return has_orig && original.GetLayerDefn()->GetFieldIndex("orig_fid") < 0 ? "orig_fid" : "";
}

LayerData read_some(LayerSource source, const std::string& key, const std::vector<std::string>& fields)
{
    LayerData data = read_layer(source.dataset, source.layer, key, fields);
    if (data.features.empty()) {
        const bool filtered = source.layer.GetSpatialFilter() != nullptr;
        throw io_error(source.dataset.GetDescription(), source.layer.GetName(),
                       filtered ? "no feature in --bbox" : "no features read");
    }
    return data;
}

} // namespace

LayerPair read_pair(LayerSource original, LayerSource snapped, const std::string& key_field)
{
    check_key(original.layer, key_field);
    check_key(snapped.layer, key_field);
    const std::vector<std::string> fields = common_fields(original.layer, snapped.layer);
    const std::string key_b = snapped_key(original.layer, snapped.layer, key_field);
    LayerPair pair{read_some(original, key_field, fields), read_some(snapped, key_b, fields), "fid"};
    if (!key_field.empty()) {
        pair.matched_by = "key " + key_field;
    } else if (!key_b.empty()) {
        pair.matched_by = "orig_fid";
    }
    return pair;
}

LayerPair read_single(LayerSource layer, const std::string& key_field)
{
    check_key(layer.layer, key_field);
    LayerData a = read_some(layer, key_field, {});
    LayerData b = a;
    return LayerPair{std::move(a), std::move(b), key_field.empty() ? "fid" : "key " + key_field};
}

} // namespace trisnap::assess
