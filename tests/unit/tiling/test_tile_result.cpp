// A tile's result round-trips bit for bit: result-<group> (the tile report, every field and
// engine counter, then its pieces: whole geometries or owned edges, with problems) and
// seams-<group> (seam edges), hand-made with awkward values and as a real tiled run wrote them.
#include "generators.hpp"
#include "record_checks.hpp"
#include "snap_harness.hpp"
#include "spool_input.hpp"

#include "stitch/spool.hpp"
#include "stitch/tiled_snap.hpp"
#include "tiling/records.hpp"
#include "tiling/work_store.hpp"

#include <gtest/gtest.h>

#include <tuple>

namespace trisnap {
namespace {

using namespace test_records;

SnapStats numbered_stats()
{
    SnapStats s;
    std::size_t n = 1;
    for (std::size_t* v : {&s.input_features, &s.input_vertices, &s.triangulation_vertices, &s.output_vertices,
                           &s.intersections, &s.merges, &s.splits, &s.rounds, &s.faces_visited, &s.fixpoint_misses,
                           &s.collapsed_features}) {
        *v = n++ * 1000003;
    }
    s.max_displacement = -0.0;
    s.seconds_triangulate = k_payload_nan;
    s.seconds_snap = 5e-324;
    s.seconds_label = 1.5;
    s.seconds_extract = 1e300;
    return s;
}

void expect_same_stats(const SnapStats& a, const SnapStats& b)
{
    EXPECT_EQ(a.input_features, b.input_features);
    EXPECT_EQ(a.input_vertices, b.input_vertices);
    EXPECT_EQ(a.triangulation_vertices, b.triangulation_vertices);
    EXPECT_EQ(a.output_vertices, b.output_vertices);
    EXPECT_EQ(a.intersections, b.intersections);
    EXPECT_EQ(a.merges, b.merges);
    EXPECT_EQ(a.splits, b.splits);
    EXPECT_EQ(a.rounds, b.rounds);
    EXPECT_EQ(a.faces_visited, b.faces_visited);
    EXPECT_EQ(a.fixpoint_misses, b.fixpoint_misses);
    EXPECT_EQ(a.collapsed_features, b.collapsed_features);
    EXPECT_EQ(bits(a.max_displacement), bits(b.max_displacement));
    EXPECT_EQ(bits(a.seconds_triangulate), bits(b.seconds_triangulate));
    EXPECT_EQ(bits(a.seconds_snap), bits(b.seconds_snap));
    EXPECT_EQ(bits(a.seconds_label), bits(b.seconds_label));
    EXPECT_EQ(bits(a.seconds_extract), bits(b.seconds_extract));
}

TEST(TileResultRecords, TileReportRoundTripsEveryField)
{
    stitch::TileReport t;
    t.id = 17;
    t.leaves = 3;
    t.core = tiling::Box{-0.0, -1e308, 1e308, std::nextafter(2.0, 3.0)};
    t.halo = 0.125;
    t.growths = 2;
    t.cascade_unbounded = true;
    t.cascade_x = k_payload_nan;
    t.cascade_y = -0.0;
    t.cascade_rank = 1ull << 40;
    t.features = 11;
    t.input_vertices = 12;
    t.output_edges_owned = 13;
    t.problems = 14;
    t.seconds = 0.75;
    t.runs = 4;
    t.stats = numbered_stats();
    t.failed = true;
    t.failure = std::string("engine threw: \0 inside", 22);
    const stitch::TileReport back = round_trip(t, stitch::put_tile_report, stitch::get_tile_report);
    EXPECT_EQ(back.id, t.id);
    EXPECT_EQ(back.leaves, t.leaves);
    for (auto [a, b] : {std::pair{t.core.xmin, back.core.xmin}, {t.core.ymin, back.core.ymin},
                        {t.core.xmax, back.core.xmax}, {t.core.ymax, back.core.ymax}, {t.halo, back.halo},
                        {t.cascade_x, back.cascade_x}, {t.cascade_y, back.cascade_y}, {t.seconds, back.seconds}}) {
        EXPECT_EQ(bits(a), bits(b));
    }
    EXPECT_EQ(back.growths, t.growths);
    EXPECT_EQ(back.cascade_unbounded, t.cascade_unbounded);
    EXPECT_EQ(back.cascade_rank, t.cascade_rank);
    EXPECT_EQ(back.features, t.features);
    EXPECT_EQ(back.input_vertices, t.input_vertices);
    EXPECT_EQ(back.output_edges_owned, t.output_edges_owned);
    EXPECT_EQ(back.problems, t.problems);
    EXPECT_EQ(back.runs, t.runs);
    expect_same_stats(t.stats, back.stats);
    EXPECT_EQ(back.failed, t.failed);
    EXPECT_EQ(back.failure, t.failure);
}

std::size_t same_problems(const std::vector<Problem>& a, const std::vector<Problem>& b)
{
    EXPECT_EQ(a.size(), b.size());
    std::size_t compared = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        EXPECT_EQ(a[i].feature_id, b[i].feature_id);
        EXPECT_EQ(a[i].code, b[i].code);
        EXPECT_EQ(a[i].message, b[i].message);
        EXPECT_EQ(bits(a[i].x), bits(b[i].x));
        EXPECT_EQ(bits(a[i].y), bits(b[i].y));
        ++compared;
    }
    return compared;
}

std::size_t same_edges(const std::vector<DirectedEdge>& a, const std::vector<DirectedEdge>& b, bool has_z)
{
    EXPECT_EQ(a.size(), b.size());
    std::size_t compared = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        compared += same_points({a[i].a, a[i].b}, {b[i].a, b[i].b}, has_z);
    }
    return compared;
}

std::size_t same_piece(const stitch::Piece& a, const stitch::Piece& b)
{
    EXPECT_EQ(a.rank, b.rank);
    EXPECT_EQ(bits(a.displacement), bits(b.displacement));
    EXPECT_EQ(a.whole, b.whole);
    EXPECT_EQ(a.has_z, b.has_z);
    std::size_t compared = same_problems(a.problems, b.problems);
    EXPECT_EQ(a.shared.size(), b.shared.size());
    for (std::size_t i = 0; i < std::min(a.shared.size(), b.shared.size()); ++i) {
        const SharedBoundary& x = a.shared[i];
        const SharedBoundary& y = b.shared[i];
        EXPECT_EQ(x.other, y.other);
        EXPECT_EQ(x.other_position, y.other_position);
        EXPECT_EQ(std::tie(x.before, x.after), std::tie(y.before, y.after));
        EXPECT_EQ(bits(x.x), bits(y.x));
        EXPECT_EQ(bits(x.y), bits(y.y));
        EXPECT_EQ(bits(x.length), bits(y.length));
        ++compared;
    }
    compared += same_geometry(a.geometry, b.geometry);
    if (!a.whole) {
        compared += same_edges(a.edges, b.edges, a.has_z);
    }
    return compared;
}

TEST(TileResultRecords, PiecesRoundTripBitForBit)
{
    stitch::Piece whole;
    whole.rank = 7;
    whole.displacement = -0.0;
    whole.whole = true;
    whole.has_z = true;
    whole.geometry = awkward_geometry(true);
    whole.problems = {Problem{-3, ProblemCode::not_converged, "a message", k_payload_nan, -0.0},
                      Problem{4, ProblemCode::self_intersection, "", 1e-300, 1e300}};
    whole.shared = {SharedBoundary{-(1ll << 60), ~0ull, true, false, -0.0, k_payload_nan, 1e-300},
                    SharedBoundary{5, 3, false, true, 0.0, 0.0, 0.0}};
    std::size_t compared = same_piece(whole, round_trip(whole, stitch::put_piece, stitch::get_piece));
    EXPECT_EQ(compared, 2u + 2u + 15u);
    for (bool has_z : {true, false}) {
        stitch::Piece cut;
        cut.rank = 1ull << 50;
        cut.displacement = k_payload_nan;
        cut.has_z = has_z;
        const Path p = awkward_path(0);
        for (std::size_t i = 0; i + 1 < p.size(); ++i) {
            cut.edges.push_back(DirectedEdge{p[i], p[i + 1]});
        }
        compared = same_piece(cut, round_trip(cut, stitch::put_piece, stitch::get_piece));
        EXPECT_EQ(compared, 8u);
        // with finished polygons after the edges
        cut.geometry = awkward_geometry(true);
        cut.geometry.has_z = has_z;
        compared = same_piece(cut, round_trip(cut, stitch::put_piece, stitch::get_piece));
        EXPECT_GT(compared, 8u);
    }
}

TEST(TileResultRecords, SeamEdgesRoundTripBitForBit)
{
    stitch::SeamEdge e;
    e.rank = 99;
    e.edge = DirectedEdge{{-0.0, 1e-300, k_payload_nan}, {1.7e308, -0.0, std::nan("")}};
    e.owned = true;
    e.near = {0, 5, 4294967295u};
    const stitch::SeamEdge back = round_trip(e, stitch::put_seam_edge, stitch::get_seam_edge);
    EXPECT_EQ(back.rank, e.rank);
    EXPECT_EQ(same_edges({e.edge}, {back.edge}, true), 2u);
    EXPECT_EQ(back.owned, e.owned);
    EXPECT_EQ(back.near, e.near);
    EXPECT_TRUE(stitch::seam_equal(e, back));
}

// A real tiled run's result and seam files: every record decodes, and encodes again to the same
// bytes (so nothing the tile wrote is lost on the way to the stitch); some pieces were cut (edges)
// and some whole, some with Z.
TEST(TileResultRecords, FilesOfARealRunDecodeAndEncodeToTheSameBytes)
{
    const double t = 0.01;
    std::vector<Feature> input = perturbed_grid_coverage(12, 12, 1.0, 0.2, 7, 1, 0.004);
    for (std::size_t i = 0; i < input.size(); i += 2) {
        input[i].geometry.has_z = true;
        for (Polygon& p : input[i].geometry.polygons) {
            for (Path& r : p.rings) {
                for (Coord& c : r) {
                    c.z = c.x * 0.5 - c.y;
                }
            }
        }
    }
    Feature islands; // one feature over every tile: its islands are finished in their tiles
    islands.id = 1000;
    islands.geometry.type = Geometry::Type::MultiPolygon;
    for (int i = 0; i < 12; ++i) {
        const double x = 0.3 + i, y = 0.4 + (i * 7) % 12;
        islands.geometry.polygons.push_back(Polygon{{{{x, y}, {x + 0.2, y}, {x + 0.2, y + 0.2}, {x, y + 0.2}, {x, y}}}});
    }
    input.push_back(islands);
    auto store = tiling::make_memory_store();
    stitch::SpoolMeta meta = spool_features(*store, input, t, 100000, 1 << 10);
    stitch::TilingOptions tiling;
    tiling.plan.tile_size = 3.0;
    tiling.threads = 1;
    stitch::TiledRun run(*store, options_at(t), tiling, stitch::ScheduleOptions{});
    run.plan(meta);
    run.snap();
    std::size_t reports = 0, whole = 0, cut = 0, finished = 0, with_z = 0, seams = 0;
    for (std::size_t g : run.groups().live(run.layout())) {
        for (const std::string& name : {stitch::files::result(g), stitch::files::seams(g)}) {
            const auto file = store->open(name);
            tiling::RecordReader reader(*file);
            std::string record;
            bool first = true;
            while (reader.next(record)) {
                std::string again;
                tiling::ByteWriter w(again);
                tiling::ByteReader r(record, "test");
                if (name == stitch::files::seams(g)) {
                    stitch::put_seam_edge(w, stitch::get_seam_edge(r));
                    ++seams;
                } else if (first) {
                    stitch::put_tile_report(w, stitch::get_tile_report(r));
                    ++reports;
                } else {
                    const stitch::Piece p = stitch::get_piece(r);
                    stitch::put_piece(w, p);
                    ++(p.whole ? whole : cut);
                    finished += p.whole ? 0 : p.geometry.polygons.size();
                    with_z += p.has_z ? 1 : 0;
                }
                first = false;
                EXPECT_TRUE(r.done()) << name;
                EXPECT_EQ(again, record) << name;
            }
        }
    }
    EXPECT_GT(reports, 4u);
    EXPECT_GT(whole, 0u);
    EXPECT_GT(cut, 0u);
    EXPECT_GT(finished, 0u);
    EXPECT_GT(with_z, 0u);
    EXPECT_GT(seams, 0u);
}

} // namespace
} // namespace trisnap
