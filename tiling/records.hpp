#pragma once
// The compact binary records of the work directory, each round-tripping bit for bit (z too):
//  - a cleaned input feature (features.bin, in input order): what the engine's cleaning kept;
//  - a tile's input feature (a bucket): engine input, whole or cut to the tile's box;
//  - directed edges, problems, and geometries (tile results).
#include "core/assemble.hpp"
#include "core/geometry.hpp"
#include "core/input_cleaning.hpp"
#include "core/problems.hpp"
#include "tiling/binary_io.hpp"

#include <cstdint>
#include <vector>

namespace trisnap::tiling {

void put_geometry(ByteWriter& w, const Geometry& g);
Geometry get_geometry(ByteReader& r);

/// A cleaned feature; `index` carries its input position (seq), `has_z` its Z flag. `outline`:
/// every ring and line read back as its first point only (counts and flags complete).
void put_clean_feature(ByteWriter& w, const detail::CleanFeature& f, bool has_z);
detail::CleanFeature get_clean_feature(ByteReader& r, bool& has_z, bool outline = false);
/// The record put_clean_feature() makes of a cleaned feature's outline (each ring and line cut
/// to its first point), made from the whole feature's record without decoding it.
void put_clean_outline(ByteWriter& w, ByteReader& whole);

/// One feature given to a tile: its rank in features.bin (input order), engine id and whether
/// it came whole.
struct TileFeature {
    std::uint64_t rank = 0;
    Feature feature;
    bool intact = true;
};
void put_tile_feature(ByteWriter& w, const TileFeature& f);
TileFeature get_tile_feature(ByteReader& r);

void put_edges(ByteWriter& w, const std::vector<DirectedEdge>& edges, bool has_z);
std::vector<DirectedEdge> get_edges(ByteReader& r);

void put_problem(ByteWriter& w, const Problem& p);
Problem get_problem(ByteReader& r);

} // namespace trisnap::tiling
