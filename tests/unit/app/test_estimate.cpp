// The one estimator of a snap run (src/app/estimate.hpp): monotone in what it is given, and
// within 2x of runs measured on ../shared/data (bench/README.md "Estimates").
#include "app/estimate.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace trisnap {
namespace {

EstimateSettings settings(bool tiled, unsigned threads)
{
    EstimateSettings s;
    s.tiled = tiled;
    s.threads = threads;
    return s;
}

EstimateInput layer(std::int64_t vertices, std::int64_t features, std::uint64_t bytes = 0, bool osm = false)
{
    EstimateInput in;
    in.vertices = vertices;
    in.features = features;
    in.input_bytes = bytes;
    in.osm = osm;
    return in;
}

TEST(Estimate, GrowsWithVerticesFeaturesAndOsmBytes)
{
    for (const EstimateSettings& s : {settings(true, 1), settings(true, 2), settings(false, 2)}) {
        RunEstimate before = estimate_run(layer(0, 0), s);
        for (std::int64_t v = 1000; v <= 100000000; v *= 3) {
            const RunEstimate e = estimate_run(layer(v, v / 10), s);
            EXPECT_GT(e.peak_bytes, before.peak_bytes) << v;
            EXPECT_GT(e.cpu_seconds, before.cpu_seconds) << v;
            EXPECT_GT(e.wall_seconds, before.wall_seconds) << v;
            before = e;
        }
        EXPECT_GT(estimate_run(layer(1000, 500), s).cpu_seconds, estimate_run(layer(1000, 5), s).cpu_seconds);
        EXPECT_GT(estimate_run(layer(1000, 5, 2000000, true), s).peak_bytes,
                  estimate_run(layer(1000, 5, 1000000, true), s).peak_bytes);
    }
}

TEST(Estimate, SettingsChangeItTheWayTheRunDoes)
{
    const EstimateInput big = layer(2000000, 100000);
    // Tiles hold a budget of vertices each, one triangulation holds them all.
    EXPECT_LT(estimate_run(big, settings(true, 2)).peak_bytes, estimate_run(big, settings(false, 2)).peak_bytes);
    // More threads: more tiles in flight, sooner done; the same work.
    EXPECT_GE(estimate_run(big, settings(true, 4)).peak_bytes, estimate_run(big, settings(true, 2)).peak_bytes);
    EXPECT_LT(estimate_run(big, settings(true, 4)).wall_seconds, estimate_run(big, settings(true, 1)).wall_seconds);
    EXPECT_DOUBLE_EQ(estimate_run(big, settings(true, 4)).cpu_seconds, estimate_run(big, settings(true, 1)).cpu_seconds);
    // Without tiles the threads do not help.
    EXPECT_DOUBLE_EQ(estimate_run(big, settings(false, 4)).wall_seconds, estimate_run(big, settings(false, 4)).cpu_seconds);
    // A smaller vertex budget: smaller tiles in flight.
    EstimateSettings small = settings(true, 2);
    small.vertex_budget = 10000;
    EXPECT_LT(estimate_run(big, small).peak_bytes, estimate_run(big, settings(true, 2)).peak_bytes);
    // Out of core: the peak stays under the limit, at some cost in time.
    EstimateSettings limited = settings(true, 2);
    limited.memory_limit = 256ull << 20;
    EXPECT_LE(estimate_run(big, limited).peak_bytes, limited.memory_limit);
    EXPECT_GT(estimate_run(big, limited).cpu_seconds, estimate_run(big, settings(true, 2)).cpu_seconds);
}

TEST(Estimate, SizeBoundIsAnUpperBoundOfUncompressedLayers)
{
    EstimateInput in = layer(-1, -1, 16000000);
    EXPECT_EQ(vertices_bound(in), 1000000); // 16 bytes per 2D vertex at least
    const RunEstimate bounded = estimate_run(in, settings(true, 2));
    EXPECT_FALSE(bounded.vertices_counted);
    EXPECT_EQ(bounded.vertices, 1000000);
    in.vertices = 400000; // what a count finds in the same file
    const RunEstimate counted = estimate_run(in, settings(true, 2));
    EXPECT_TRUE(counted.vertices_counted);
    EXPECT_LT(counted.peak_bytes, bounded.peak_bytes);
}

struct Measured {
    std::string name;
    EstimateInput in;
    bool tiled;
    double peak_mib; ///< peak RSS of `trisnap snap --threads 2 --tolerance-m 0.01`
    double cpu;      ///< user + sys seconds
};

TEST(Estimate, WithinTwiceTheMeasuredRuns)
{
    // bench/README.md "Estimates" (2 threads, 1 cm): peak RSS measured 2026-11-23 (load 5-8 on 2
    // cores; what the memory constants are calibrated on), CPU time 2026-11-28 (load ~1; the
    // time constants' calibration, after the lean engine).
    const std::vector<Measured> runs = {
        {"natural_earth ne_10m_land", layer(411137, 10, 19431424), true, 291, 1.46},
        {"natural_earth ne_10m_land", layer(411137, 10, 19431424), false, 467, 1.76},
        {"natural_earth ne_50m_admin_0_countries", layer(99593, 241, 19431424), true, 147, 0.48},
        {"boston buildings", layer(273340, 48124, 10874880), true, 212, 1.52},
        {"boston buildings", layer(273340, 48124, 10874880), false, 310, 1.93},
        {"snapoly andorra", layer(44661, 5757, 1642496), true, 103, 0.36},
        {"bgt_delft bgt_kunstwerkdeel (5 vertices)", layer(5, 1, 1720320), true, 57, 0.15},
        {"monaco 2020 .osm.pbf multipolygons", layer(208489, 24084, 1759101, true), true, 309, 1.73},
        {"andorra 2013 .osm.pbf multipolygons", layer(17138, 624, 565390, true), true, 102, 0.43},
        // validate does not read an .osm.pbf: the vertices from the file's size.
        {"monaco 2020 .osm.pbf, not counted", layer(-1, -1, 1759101, true), true, 309, 1.73},
        {"helsinki 2020 .osm.pbf, not counted", layer(-1, -1, 685110, true), true, 106, 0.44},
    };
    for (const Measured& m : runs) {
        const RunEstimate e = estimate_run(m.in, settings(m.tiled, 2));
        const double mib = static_cast<double>(e.peak_bytes) / 1048576.0;
        EXPECT_LE(mib, 2 * m.peak_mib) << m.name;
        EXPECT_GE(mib, m.peak_mib / 2) << m.name;
        EXPECT_LE(e.cpu_seconds, 2 * m.cpu) << m.name;
        EXPECT_GE(e.cpu_seconds, m.cpu / 2) << m.name;
    }
}

} // namespace
} // namespace trisnap
