#pragma once
// Engine tests that hold the mesh themselves (to read its counters or call its searches): the
// snapper run on it with the engine's thresholds at t.
#include "core/mesh.hpp"
#include "core/snapper.hpp"

namespace trisnap {

/// The snapper on `mesh` with the engine's thresholds at t (edge and sliver t/2, no margins),
/// its operation cap, and the fix-point verified.
inline detail::SnapperOutcome run_snapper_at(detail::Mesh& mesh, double t)
{
    detail::SnapperParams params;
    params.vertex_threshold = t;
    params.edge_threshold = t / 2;
    params.sliver_threshold = t / 2;
    params.max_operations = 20 * mesh.vertex_slots() + 1000;
    params.verify = true;
    return detail::run_snapper(mesh, params);
}

} // namespace trisnap
