#pragma once
// Reading the two layers assess compares: the fields they share, and the key that matches
// their features (--key, else an `orig_fid` field of the snapped layer, else the FID).
#include "assess/assess.hpp"
#include "assess/layer_data.hpp"

#include <string>

namespace trisnap::assess {

struct LayerPair {
    LayerData a;
    LayerData b;
    std::string matched_by; // "fid", "orig_fid" or "key FIELD"
};

/// Reads both layers. Throws std::invalid_argument when `key_field` is missing from either
/// layer (the message lists the fields), io_error when a layer cannot be read or yields no
/// feature (0 features read is an error, never an empty measurement).
LayerPair read_pair(LayerSource original, LayerSource snapped, const std::string& key_field);

/// One layer compared with itself (render without a snapped layer): read once.
LayerPair read_single(LayerSource layer, const std::string& key_field);

} // namespace trisnap::assess
