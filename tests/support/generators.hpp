#pragma once
// Deterministic synthetic layers for property tests and benchmarks. Every generator draws from
// std::mt19937_64 (whose sequence the standard fixes) through our own mapping to doubles and
// integers, so a seed gives the same features with any standard library. Ids start at 1.
#include "core/geometry.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace trisnap {

/// Uniform double in [lo, hi) from the top 53 bits of one draw.
double uniform(std::mt19937_64& rng, double lo, double hi);
/// Integer in [lo, hi] (tiny modulo bias, irrelevant here and stable across platforms).
std::int64_t uniform_int(std::mt19937_64& rng, std::int64_t lo, std::int64_t hi);

/// A planar partition of nx*ny quadrilaterals over [0, nx*cell] x [0, ny*cell]. Interior
/// corners move by up to jitter*cell in x and y (jitter < 0.25 keeps cells convex enough);
/// border corners slide along the border only, so the union is exactly the rectangle. Each edge
/// gets `points_per_edge` extra vertices, wiggled sideways by up to edge_wiggle*cell (0 on the
/// border), written identically into both neighbours: shared edges are exactly shared.
/// Vertex count is about nx*ny*(5 + 4*points_per_edge).
std::vector<Feature> perturbed_grid_coverage(int nx, int ny, double cell, double jitter,
                                             std::uint64_t seed, int points_per_edge = 0,
                                             double edge_wiggle = 0.002);

/// n small valid polygons around [0, scale]^2 built to stress snapping at tolerance t: star-shaped
/// rings with near-coincident vertices (0.1t..0.5t apart), spikes, some holes, slivers thinner
/// than t, and polygons placed with a vertex 0.1t..0.5t outside another polygon's edge. Inputs
/// may overlap each other (like OSM layers), never themselves.
std::vector<Feature> near_degenerate_polygons(int n, double scale, double t, std::uint64_t seed);

/// k >= 3 triangles fanning out from a cluster: each has one vertex within t/2 of the origin
/// and two at about 10t, in disjoint angular sectors, so the triangles do not overlap.
std::vector<Feature> vertex_cluster(int k, double t, std::uint64_t seed);

/// An axis-aligned square as a closed counter-clockwise ring.
Feature square(std::int64_t id, double x0, double y0, double size);

/// One linestring of n vertices along the x axis, `spacing` apart, each moved sideways by up
/// to wiggle (for "many points closer than t" merge chains).
Feature dense_line(std::int64_t id, int n, double spacing, double wiggle, std::uint64_t seed);

/// n axis-aligned squares of the given side at uniform random corners in [0, extent)^2 (they may
/// overlap): at a tolerance of several sides every square collapses and neighbours merge into
/// clusters.
std::vector<Feature> random_small_squares(int n, double side, double extent, std::uint64_t seed);

/// One square ring [0, side]^2 with about n vertices evenly spaced along its sides (n/4 per side):
/// at t above the spacing, long chains of collinear merges.
Feature densified_square(std::int64_t id, int n, double side);

/// One ring of n vertices on the circle of the given radius around the origin, each moved by up
/// to `jitter` in x and y (0: exactly on the circle, which makes the triangulation's inside a fan
/// around vertices of very high degree).
Feature circle(std::int64_t id, int n, double radius, double jitter, std::uint64_t seed);

/// An input that makes snapping expensive at `large_t` and cheap at `small_t` (issue 13's list).
struct AdversarialCase {
    const char* name;
    std::vector<Feature> features;
    double small_t;
    double large_t;
};

/// Issue 13's adversarial inputs, scaled by `scale` (1: the sizes the issue measured; the slow
/// test uses smaller ones): random squares at t = 10 sides, a densified square and an exact and a
/// jittered circle with neighbours closer than t, and squares packed denser with the size inside
/// a frame of long edges. JTS's ReducePrecisionFailure case comes from
/// ../shared/data and is added by the callers that have it.
std::vector<AdversarialCase> adversarial_cases(double scale);

/// Total vertex count, closing points included (as GDAL counts them).
std::size_t vertex_count(const std::vector<Feature>& features);

} // namespace trisnap
