#pragma once
// A vector of features spooled into a work store the way the read phase does (FeatureSpool),
// for the tests that drive TiledRun's phases themselves.
#include "core/geometry.hpp"
#include "stitch/spool.hpp"
#include "tiling/work_store.hpp"

#include <cstddef>
#include <vector>

namespace trisnap {

/// Spools `input` (sequence numbers 0..n-1) at tolerance t; `sample_cap` and `fid_buffer` as
/// FeatureSpool's (small values exercise the sampled plan and FID runs).
inline stitch::SpoolMeta spool_features(tiling::WorkStore& store, const std::vector<Feature>& input, double t,
                                        std::size_t sample_cap = 100000, std::size_t fid_buffer = 1 << 16)
{
    stitch::FeatureSpool spool(store, t, sample_cap, fid_buffer);
    std::vector<Problem> problems;
    for (std::size_t i = 0; i < input.size(); ++i) {
        spool.add(i, input[i].id, input[i].geometry, problems);
    }
    return spool.finish();
}

} // namespace trisnap
