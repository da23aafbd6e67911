#pragma once
// The closest vertex–vertex and vertex–edge pairs of one layer, closer than the tolerance.
#include "render/sites.hpp"

namespace trisnap::render {

/// Appends, for every distinct vertex of `layer`, its nearest other vertex closer than T
/// (once per pair) and its nearest edge closer than T that does not end at it (exact
/// coordinates decide incidence; an edge through a vertex that is not its endpoint counts, at
/// distance 0). Shared boundaries are counted once: vertices and edges are deduplicated first.
void add_pair_sites(const Layer& layer, double tolerance, std::vector<Site>& sites);

} // namespace trisnap::render
