#pragma once
// What one tile snaps: every input edge that meets the tile's box R (core + halo), whole and
// with its exact input coordinates, so that a tile and its neighbours see the same segments.
// Rings are closed again outside R: each run of edges that misses R is replaced by a shortcut
// or by a detour along a frame B around everything kept, chosen to go round R the same number
// of times as the run did, so the odd-even membership of every point of R is unchanged. A
// ring that misses R but encloses it becomes its bounding box. Lines keep their runs of edges
// that meet R as separate parts.
#include "core/input_cleaning.hpp"
#include "tiling/plan.hpp"

#include <memory>
#include <vector>

namespace trisnap::tiling {

struct TileInput {
    std::vector<Feature> features;   ///< engine input; ids are the input ids
    std::vector<std::size_t> source; ///< index into the cleaned features of each
    std::vector<bool> intact;        ///< given whole (no edge dropped, no detour)
    std::size_t vertices = 0;
};

bool segment_meets_box(const Coord& p, const Coord& q, const Box& b);

/// The frame detours run along: round `extent` (which holds every input vertex) and R, with room.
Box detour_frame(const Box& extent, const Box& R);

class RingCutter;

/// Cuts cleaned features for one tile box R (see the top of this file).
class TileCutter {
public:
    TileCutter(const Box& R, const Box& frame);
    ~TileCutter();
    /// The feature as the tile sees it (id = cf.id); false when nothing of it meets R.
    /// `intact`: given whole (no edge dropped, no detour).
    bool cut(const detail::CleanFeature& cf, bool has_z, Feature& out, bool& intact) const;

private:
    void cut_polygon(const detail::CleanFeature& cf, Geometry& out, bool& intact) const;
    void cut_lines(const detail::CleanFeature& cf, Geometry& out, bool& intact) const;

    Box m_r;
    std::unique_ptr<RingCutter> m_cutter;
};

/// Vertices the engine counts: rings without their closing point, lines whole.
std::size_t engine_vertices(const Geometry& g);

/// `candidates`: cleaned features whose box meets R (ascending indices); rejected ones skipped.
/// `has_z[i]`: whether cleaned feature i carries Z.
TileInput build_tile_input(const std::vector<detail::CleanFeature>& clean, const std::vector<bool>& has_z,
                           const std::vector<std::size_t>& candidates, const Box& R);

} // namespace trisnap::tiling
