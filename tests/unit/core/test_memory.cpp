// The engine's memory habits that no output shows: the searches' per-vertex scratch is dropped
// after the snapper and comes back if a search needs it, the output's rings carry no spare
// capacity (closing a ring once doubled every ring's allocation: 34 MB of heap on Andorra x43),
// the cleaned input is cut to outlines once the mesh's records hold its points, and the faces
// of each feature are held in blocks of features, each one allocation, a layer without z
// holds no z values, and the outputs are made after the triangulation is freed.
// Peak memory itself is measured by bench_pipeline (peak_mb) and bench/estimates, not here.
#include "snap_harness.hpp"

#include "generators.hpp"
#include "mesh_harness.hpp"

#include "core/extraction.hpp"
#include "core/labelling.hpp"
#include "core/snapper.hpp"
#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace trisnap {
namespace {

using Near = std::vector<std::pair<double, std::uint32_t>>;

// A mesh of near-degenerate polygons at t and, for every vertex, the vertices a search within
// 4t finds (sorted), searched once before the test does anything to the mesh.
struct SearchedMesh {
    static constexpr double t = 0.05;
    static constexpr double r2 = 16 * t * t;
    std::vector<detail::CleanFeature> clean;
    detail::Mesh mesh;
    std::vector<Near> before;

    SearchedMesh(int polygons, double scale, std::uint64_t seed)
        : clean(cleaned(near_degenerate_polygons(polygons, scale, t, seed))), mesh(clean, t)
    {
        for (std::uint32_t v = 0; v < vertices(); ++v) {
            before.push_back(search(v));
        }
    }
    std::uint32_t vertices() const { return static_cast<std::uint32_t>(mesh.vertex_slots()); }
    Near search(std::uint32_t v)
    {
        Near near;
        std::vector<detail::EdgeHit> edges;
        mesh.search_point(v, r2, r2 / 4, near, edges);
        std::sort(near.begin(), near.end());
        return near;
    }
    static std::vector<detail::CleanFeature> cleaned(const std::vector<Feature>& in)
    {
        std::vector<Problem> problems;
        return detail::clean_input(in, t, problems);
    }
};

// A search after release_search_scratch() allocates the scratch again and finds what it found
// before, for every vertex; the snapper then runs on the same mesh to its verified fix-point.
TEST(EngineMemory, SearchesAfterTheScratchIsReleasedFindTheSame)
{
    SearchedMesh m(40, 10.0, 11);
    ASSERT_GT(m.vertices(), 200u);
    std::size_t found = 0;
    for (const Near& near : m.before) found += near.size();
    EXPECT_GT(found, m.vertices()) << "the radius must reach neighbours";
    m.mesh.release_search_scratch();
    for (std::uint32_t v = 0; v < m.vertices(); ++v) {
        EXPECT_EQ(m.search(v), m.before[v]) << "vertex " << v;
    }
    m.mesh.release_search_scratch();
    const detail::SnapperOutcome out = run_snapper_at(m.mesh, SearchedMesh::t);
    EXPECT_GT(out.merges + out.splits, 10u) << "the case must make the snapper edit";
    EXPECT_TRUE(out.converged);
    EXPECT_EQ(out.fixpoint_misses, 0u);
}

// A vertex's z lives beside its record, and a layer without z holds none: not after the build,
// nor after the snapper's merges and crossings. One input point with a z makes the mesh hold
// one per vertex from the build on, that point's own among them, and NaN for the others.
TEST(EngineMemory, ALayerWithoutZHoldsNoZValues)
{
    constexpr double t = SearchedMesh::t;
    std::vector<Feature> flat = near_degenerate_polygons(40, 10.0, t, 11);
    {
        std::vector<detail::CleanFeature> clean = SearchedMesh::cleaned(flat);
        detail::Mesh mesh(clean, t);
        EXPECT_FALSE(mesh.holds_z());
        const detail::SnapperOutcome out = run_snapper_at(mesh, t);
        EXPECT_GT(out.merges + out.splits, 10u) << "the case must make the snapper edit";
        EXPECT_FALSE(mesh.holds_z());
    }
    Coord& first = flat.front().geometry.polygons.front().rings.front().front();
    first.z = 7.5;
    flat.front().geometry.polygons.front().rings.front().back().z = 7.5; // the closing point
    std::vector<detail::CleanFeature> clean = SearchedMesh::cleaned(flat);
    detail::Mesh mesh(clean, t);
    ASSERT_TRUE(mesh.holds_z());
    std::size_t with_z = 0;
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) {
        if (!std::isnan(mesh.z(v))) {
            ++with_z;
            EXPECT_EQ(mesh.z(v), 7.5);
            EXPECT_EQ(mesh.vertex(v).x, first.x);
            EXPECT_EQ(mesh.vertex(v).y, first.y);
        }
    }
    EXPECT_EQ(with_z, 1u);
    // Merges take the mean of the z values they have (7.5) and an edge to a point without z
    // gives none: every z stays 7.5 or NaN, and one live vertex carries the point's.
    const detail::SnapperOutcome out = run_snapper_at(mesh, t);
    EXPECT_GT(out.merges + out.splits, 10u);
    std::size_t alive_with_z = 0;
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) {
        EXPECT_TRUE(std::isnan(mesh.z(v)) || mesh.z(v) == 7.5) << "vertex " << v << ": " << mesh.z(v);
        alive_with_z += mesh.vertex(v).alive && mesh.z(v) == 7.5 ? 1 : 0;
    }
    EXPECT_EQ(alive_with_z, 1u);
}

// A vertex's point lives in its CGAL vertex while it is in the triangulation and in the mesh's
// kept points once it is out (VertexSlot): removed by the snapper's merges and splits, or with
// the whole triangulation. Every vertex reads the same point throughout: its CGAL point before
// the snapper, the input's for every input point (merged or not), and after the release what
// it read before; handles are null exactly for the vertices out of the triangulation.
TEST(EngineMemory, EveryVertexKeepsItsPointOutOfTheTriangulation)
{
    constexpr double t = SearchedMesh::t;
    const std::vector<Feature> in = near_degenerate_polygons(40, 10.0, t, 13);
    const std::vector<detail::CleanFeature> clean = SearchedMesh::cleaned(in);
    detail::Mesh mesh(clean, t);
    std::vector<detail::Xy> before(mesh.vertex_slots());
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) {
        const detail::VertexRecord r = mesh.vertex(v);
        ASSERT_TRUE(r.handle != cdt::Vertex_handle()) << "vertex " << v;
        EXPECT_EQ(r.x, r.handle->point().x());
        EXPECT_EQ(r.y, r.handle->point().y());
        before[v] = mesh.xy(v);
    }
    const detail::SnapperOutcome out = run_snapper_at(mesh, t);
    ASSERT_GT(out.merges, 10u) << "the case must remove vertices";
    std::size_t removed = 0;
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) {
        const detail::VertexRecord r = mesh.vertex(v);
        EXPECT_EQ(r.handle != cdt::Vertex_handle(), r.alive) << "vertex " << v;
        removed += r.alive ? 0 : 1;
        if (v < before.size()) {
            EXPECT_EQ(r.x, before[v].x) << "vertex " << v;
            EXPECT_EQ(r.y, before[v].y) << "vertex " << v;
        }
        if (r.alive) {
            EXPECT_EQ(r.x, r.handle->point().x()) << "vertex " << v;
            EXPECT_EQ(r.y, r.handle->point().y()) << "vertex " << v;
        }
    }
    ASSERT_GT(removed, 10u);
    for (std::size_t f = 0; f < clean.size(); ++f) {
        std::vector<Coord> points;
        for (const detail::CleanRing& ring : clean[f].rings) {
            points.insert(points.end(), ring.points.begin(), ring.points.end());
            points.push_back(ring.points.front());
        }
        const auto ids = mesh.input_vertices(f);
        ASSERT_EQ(ids.size(), points.size());
        for (std::size_t k = 0; k < ids.size(); ++k) {
            EXPECT_EQ(mesh.xy(ids[k]).x, points[k].x) << "feature " << f << " point " << k;
            EXPECT_EQ(mesh.xy(ids[k]).y, points[k].y) << "feature " << f << " point " << k;
        }
    }
    std::vector<detail::Xy> snapped(mesh.vertex_slots());
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) snapped[v] = mesh.xy(v);
    mesh.release_search_scratch();
    mesh.release_triangulation();
    for (std::uint32_t v = 0; v < mesh.vertex_slots(); ++v) {
        const detail::VertexRecord r = mesh.vertex(v);
        EXPECT_TRUE(r.handle == cdt::Vertex_handle()) << "vertex " << v;
        EXPECT_EQ(r.x, snapped[v].x) << "vertex " << v;
        EXPECT_EQ(r.y, snapped[v].y) << "vertex " << v;
    }
}

// A face keeps its stamp in 28 bits (a 56-byte face): the counter wraps at cdt::k_stamp_limit
// and clears every mark. Searches on both sides of the wrap find what they find far from it;
// with the wrap past the field's width a stored stamp would lose its top bits and never match,
// and the walks would revisit faces.
TEST(EngineMemory, SearchesAcrossTheStampWrapFindTheSame)
{
    SearchedMesh m(20, 5.0, 3);
    const std::uint32_t n = m.vertices();
    ASSERT_GT(n, 100u);
    m.mesh.set_stamps_used(cdt::k_stamp_limit - n / 2); // the wrap falls halfway through
    std::size_t faces = m.mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        EXPECT_EQ(m.search(v), m.before[v]) << "vertex " << v;
    }
    EXPECT_LT(m.mesh.stamps_used(), n) << "the counter must have wrapped";
    const std::size_t across = m.mesh.faces_walked() - faces;
    faces = m.mesh.faces_walked();
    for (std::uint32_t v = 0; v < n; ++v) {
        m.search(v);
    }
    EXPECT_EQ(across, m.mesh.faces_walked() - faces) << "the walks across the wrap visit each face once, as far from it";
}

// Every output ring's allocation is its size: the closing point had room made for it.
TEST(EngineMemory, OutputRingsHoldNoSpareCapacity)
{
    const double t = 0.05;
    const std::vector<Feature> in = perturbed_grid_coverage(12, 12, 1.0, 0.1, 5, 3);
    const CheckedRun run = snap_and_check(in, options_at(t), 0);
    EXPECT_TRUE(contract_holds(run.report, t));
    std::size_t rings = 0;
    for (const FeatureOutput& f : run.result.features) {
        for (const Polygon& p : f.geometry.polygons) {
            for (const Path& ring : p.rings) {
                ++rings;
                EXPECT_EQ(ring.capacity(), ring.size()) << "feature " << f.id;
            }
        }
    }
    EXPECT_EQ(rings, in.size());
}

// Mesh's outlining constructor frees the cleaned features once the vertex records hold their
// points and keeps their outlines: every input point is then read back exactly from the
// records, feature by feature, rings (closed) then lines, every outline field is the feature's,
// every input edge's owner names its two ends, and the mesh is the one a build that keeps the
// copy makes.
TEST(EngineMemory, OutlinedInputIsInTheRecords)
{
    const double t = 0.05;
    std::vector<Feature> in = near_degenerate_polygons(30, 10.0, t, 7);
    in.push_back(dense_line(1000, 200, 0.02, 0.3, 5));
    in.push_back(dense_line(1001, 50, 0.1, 0.0, 6));
    // Rings of different sizes in one feature: a shell of 40 points with a square hole, and a
    // second part of 4 (two parts of one multipolygon, so each path's size must be its own).
    Feature holed = densified_square(1002, 40, 4.0);
    Feature hole = square(0, 1.0, 1.0, 1.0);
    std::reverse(hole.geometry.polygons[0].rings[0].begin(), hole.geometry.polygons[0].rings[0].end());
    holed.geometry.polygons[0].rings.push_back(hole.geometry.polygons[0].rings[0]);
    holed.geometry.polygons.push_back(square(0, 6.0, 0.0, 1.0).geometry.polygons[0]);
    holed.geometry.type = Geometry::Type::MultiPolygon;
    in.push_back(holed);
    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> full = detail::clean_input(in, t, problems);
    std::vector<detail::CleanFeature> cut = full;
    const detail::Mesh kept(full, t);
    detail::Outlines outlines;
    const detail::Mesh outlined(std::move(cut), t, nullptr, outlines);
    EXPECT_EQ(cut.capacity(), 0u) << "the cleaned copy is freed";

    ASSERT_EQ(outlines.size(), full.size());
    std::size_t points = 0, lines = 0;
    for (std::size_t f = 0; f < full.size(); ++f) {
        const detail::CleanFeature& a = full[f];
        const detail::Outline& b = outlines[f];
        EXPECT_EQ(b.index, a.index);
        EXPECT_EQ(b.id, a.id);
        EXPECT_EQ(b.polygonal, a.polygonal);
        EXPECT_EQ(b.rejected, a.rejected);
        EXPECT_EQ(b.paths, a.rings.size() + a.lines.size());
        EXPECT_EQ(b.parts, a.polygonal ? a.shells : a.lines.size());
        EXPECT_EQ(b.holes, a.holes);
        const Coord first = a.polygonal ? a.rings.front().points.front() : a.lines.front().front();
        EXPECT_EQ(b.x, first.x) << "feature " << f;
        EXPECT_EQ(b.y, first.y) << "feature " << f;
        const std::vector<Coord> starts = outlines.starts(f);
        ASSERT_EQ(starts.size(), a.lines.size()) << "feature " << f;
        std::vector<Coord> expected;
        for (const detail::CleanRing& r : a.rings) {
            expected.insert(expected.end(), r.points.begin(), r.points.end());
            expected.push_back(r.points.front()); // rings are closed in the input ids (Owner::at)
        }
        for (std::size_t l = 0; l < a.lines.size(); ++l, ++lines) {
            EXPECT_EQ(starts[l], a.lines[l].front()) << "feature " << f << " line " << l;
            expected.insert(expected.end(), a.lines[l].begin(), a.lines[l].end());
        }
        const auto ids = outlined.input_vertices(f);
        ASSERT_EQ(ids.size(), expected.size()) << "feature " << f;
        for (std::size_t k = 0; k < ids.size(); ++k, ++points) {
            const detail::Xy r = outlined.xy(ids[k]);
            EXPECT_EQ(r.x, expected[k].x) << "feature " << f << " point " << k;
            EXPECT_EQ(r.y, expected[k].y) << "feature " << f << " point " << k;
        }
    }
    EXPECT_EQ(lines, 2u);
    // The owners, in the order the build inserts features (by id), each path's edges in order.
    std::vector<std::size_t> by_id(full.size());
    std::iota(by_id.begin(), by_id.end(), 0);
    std::stable_sort(by_id.begin(), by_id.end(), [&](std::size_t a, std::size_t b) { return full[a].id < full[b].id; });
    std::uint32_t owner = 0;
    for (const std::size_t f : by_id) {
        const auto ids = outlined.input_vertices(f);
        auto check_path = [&](const std::vector<Coord>& path, bool ring) {
            const std::size_t edges = ring ? path.size() : path.size() - 1;
            for (std::size_t i = 0; i < edges; ++i, ++owner) {
                const detail::Owner& o = outlined.owner_at(owner);
                ASSERT_EQ(o.feature, f) << "owner " << owner;
                EXPECT_EQ(o.line != 0, !ring) << "owner " << owner;
                const Coord& a = path[i];
                const Coord& b = path[(i + 1) % path.size()];
                EXPECT_EQ(outlined.vertex(outlined.owner_from(o)).x, a.x) << "owner " << owner;
                EXPECT_EQ(outlined.vertex(outlined.owner_from(o)).y, a.y) << "owner " << owner;
                EXPECT_EQ(outlined.vertex(outlined.owner_to(o)).x, b.x) << "owner " << owner;
                EXPECT_EQ(outlined.vertex(outlined.owner_to(o)).y, b.y) << "owner " << owner;
            }
        };
        ASSERT_FALSE(ids.empty());
        for (const detail::CleanRing& r : full[f].rings) check_path(r.points, true);
        for (const std::vector<Coord>& l : full[f].lines) check_path(l, false);
    }
    EXPECT_EQ(outlines.features.back().paths, 3u) << "the multipolygon keeps its shell, hole and part";
    EXPECT_EQ(outlines.features.back().parts, 2u);
    EXPECT_EQ(outlines.features.back().holes, 1u);
    EXPECT_GT(points, 500u);
    // The same triangulation: the same vertices (crossings included) and constrained edges.
    ASSERT_EQ(outlined.vertex_slots(), kept.vertex_slots());
    ASSERT_GT(outlined.intersections(), 0u) << "the case must cross edges";
    for (std::uint32_t v = 0; v < kept.vertex_slots(); ++v) {
        EXPECT_EQ(outlined.vertex(v).x, kept.vertex(v).x) << "vertex " << v;
        EXPECT_EQ(outlined.vertex(v).y, kept.vertex(v).y) << "vertex " << v;
    }
    auto constrained = [](const detail::Mesh& m) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
        for (auto e = m.tri().finite_edges_begin(); e != m.tri().finite_edges_end(); ++e) {
            if (!m.tri().is_constrained(*e)) continue;
            const std::uint32_t a = m.id(e->first->vertex(m.tri().cw(e->second)));
            const std::uint32_t b = m.id(e->first->vertex(m.tri().ccw(e->second)));
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
        std::sort(edges.begin(), edges.end());
        return edges;
    };
    EXPECT_EQ(constrained(outlined), constrained(kept));
}

// label_faces places each feature's faces in blocks of FaceLabels::k_block features: across the
// block boundaries every feature's list is the finite faces inside its square (found here by
// the faces' centroids, without the labels), in the triangulation's order (what pushing them one
// by one gave); freeing one block leaves the others whole; and the faces' marks, which held the
// labels, are all 0 again for the searches' stamps.
TEST(EngineMemory, FaceListsInBlocksAreEachFeaturesFaces)
{
    const double t = 0.01;
    const std::size_t block = detail::FaceLabels::k_block;
    const std::vector<Feature> in = random_small_squares(static_cast<int>(2 * block + 100), 1.0, 200.0, 9);
    std::vector<Problem> problems;
    const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
    detail::Mesh mesh(clean, t);
    detail::FaceLabels labels = detail::label_faces(mesh, clean.size());
    ASSERT_EQ(labels.blocks.size(), 3u);
    // The squares' boxes in a grid of unit cells, to find the squares holding a point.
    struct Box {
        double x0, y0, x1, y1;
    };
    std::vector<Box> boxes;
    for (const detail::CleanFeature& cf : clean) {
        ASSERT_EQ(cf.rings.size(), 1u);
        Box b{1e300, 1e300, -1e300, -1e300};
        for (const Coord& c : cf.rings[0].points) {
            b = Box{std::min(b.x0, c.x), std::min(b.y0, c.y), std::max(b.x1, c.x), std::max(b.y1, c.y)};
        }
        boxes.push_back(b);
    }
    const int cells = 202;
    auto cell = [&](double v) { return std::clamp(static_cast<int>(std::floor(v)) + 1, 0, cells - 1); };
    std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(cells * cells));
    for (std::uint32_t f = 0; f < boxes.size(); ++f) {
        for (int i = cell(boxes[f].x0); i <= cell(boxes[f].x1); ++i) {
            for (int j = cell(boxes[f].y0); j <= cell(boxes[f].y1); ++j) grid[static_cast<std::size_t>(i * cells + j)].push_back(f);
        }
    }
    std::vector<std::vector<cdt::Face_handle>> expected(clean.size());
    std::size_t shared = 0, marked = 0;
    for (const cdt::Face_handle f : mesh.tri().all_face_handles()) {
        marked += f->info().mark != 0 ? 1 : 0;
    }
    for (const cdt::Face_handle f : mesh.tri().finite_face_handles()) {
        const cdt::Point c = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
        std::size_t in_squares = 0;
        for (const std::uint32_t k : grid[static_cast<std::size_t>(cell(c.x()) * cells + cell(c.y()))]) {
            const Box& b = boxes[k];
            if (c.x() > b.x0 && c.x() < b.x1 && c.y() > b.y0 && c.y() < b.y1) {
                expected[k].push_back(f);
                ++in_squares;
            }
        }
        shared += in_squares > 1 ? 1 : 0;
    }
    EXPECT_EQ(marked, 0u) << "labelling must leave every mark at 0, infinite faces' too";
    EXPECT_GT(shared, 0u) << "the case must hold faces of two overlapping features";
    auto same = [&](std::size_t f) {
        const std::span<const cdt::Face_handle> got = labels.faces_of(f);
        return std::equal(got.begin(), got.end(), expected[f].begin(), expected[f].end());
    };
    for (std::size_t f = 0; f < clean.size(); ++f) {
        ASSERT_GE(expected[f].size(), 2u) << "feature " << f << " is a square: two faces at least";
        EXPECT_TRUE(same(f)) << "feature " << f;
    }
    // Each set of features has one label (singletons are kept apart from the map of the others:
    // a set met both ways must still get one label), the outside's is 0, each set is sorted.
    std::set<std::vector<std::uint32_t>> sets;
    std::size_t overlapping = 0;
    for (std::uint32_t l = 0; l < labels.labels(); ++l) {
        const std::span<const std::uint32_t> s = labels.set(l);
        EXPECT_TRUE(std::is_sorted(s.begin(), s.end()) && std::adjacent_find(s.begin(), s.end()) == s.end()) << "label " << l;
        sets.emplace(s.begin(), s.end());
        overlapping += s.size() > 1 ? 1 : 0;
    }
    EXPECT_EQ(sets.size(), labels.labels()) << "a set of features with two labels";
    EXPECT_TRUE(labels.set(0).empty()) << "label 0 is the outside";
    EXPECT_GT(overlapping, 0u);
    labels.release_block(block + 7); // the middle block
    EXPECT_EQ(labels.blocks[1].capacity(), 0u);
    for (std::size_t f : {std::size_t{0}, block - 1, 2 * block, clean.size() - 1}) {
        EXPECT_TRUE(same(f)) << "feature " << f << " after the middle block was freed";
    }
}

// The snapper keeps no distance with a vertex's merge candidate: Mesh::vertex_d2 gives it again
// and must be the searches' distance bit for bit, either way round, for every pair a search
// finds (a candidate's key compared with a parked pair's in Snapper::retry_parked).
TEST(EngineMemory, PairDistancesAreTheSearchesBitForBit)
{
    SearchedMesh m(60, 10.0, 11);
    std::size_t pairs = 0;
    for (std::uint32_t v = 0; v < m.vertices(); ++v) {
        for (const auto& [d2, w] : m.before[v]) {
            if (w == v) continue;
            ++pairs;
            ASSERT_EQ(m.mesh.vertex_d2(v, w), d2) << "vertices " << v << ", " << w;
            ASSERT_EQ(m.mesh.vertex_d2(w, v), d2) << "vertices " << w << ", " << v;
        }
    }
    EXPECT_GT(pairs, 100u);
}

// The outputs are made after the triangulation is freed: each polygon's boundary edges and each
// line's edges are taken out by vertex id first (and the owner table freed), then
// Mesh::release_triangulation() frees CGAL's faces and vertices and keeps the records. Every
// feature's geometry made from the ids after the release is the one made while the mesh lived,
// on a snapped mesh with merged and split vertices (records of dead vertices among them).
TEST(EngineMemory, OutputsAfterTheTriangulationIsFreedAreTheLiveMeshs)
{
    const double t = 0.05;
    std::vector<Feature> in = near_degenerate_polygons(40, 10.0, t, 5);
    in.push_back(dense_line(2000, 300, 0.02, 0.3, 8));
    in.push_back(dense_line(2001, 60, 0.1, 0.0, 9));
    std::vector<Problem> problems;
    std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
    detail::Outlines outlines;
    detail::Mesh mesh(std::move(clean), 2 * t, nullptr, outlines);
    detail::SnapperParams params;
    params.vertex_threshold = t;
    params.edge_threshold = t / 2;
    params.max_operations = 100000;
    const detail::SnapperOutcome out = detail::run_snapper(mesh, params);
    ASSERT_TRUE(out.converged);
    ASSERT_GT(out.merges, 0u);
    ASSERT_GT(out.splits, 0u);
    mesh.release_search_scratch();
    detail::FaceLabels labels = detail::label_faces(mesh, outlines.size());
    const detail::ExtractOptions eo{0.0, false};
    std::vector<std::string> live(outlines.size());
    std::vector<std::vector<detail::IdEdge>> boundary(outlines.size());
    const detail::LineEdges lines = detail::collect_line_edges(mesh, outlines.size());
    auto starts = [&](std::size_t f) { return outlines.starts(f); };
    std::size_t polygons = 0, line_features = 0;
    for (std::size_t f = 0; f < outlines.size(); ++f) {
        if (outlines[f].polygonal) {
            detail::append_boundary_edges(mesh, labels.faces_of(f), boundary[f]);
            live[f] = to_wkt(detail::assemble_boundary(mesh, boundary[f], eo));
            polygons += live[f] != "POLYGON EMPTY" ? 1 : 0;
        } else {
            live[f] = to_wkt(detail::extract_lines(mesh, lines.of(f), starts(f), eo));
            ++line_features;
        }
    }
    EXPECT_GT(polygons, 30u);
    EXPECT_EQ(line_features, 2u);
    const std::size_t vertices = mesh.tri().number_of_vertices();
    ASSERT_GT(vertices, 100u);
    mesh.release_triangulation();
    EXPECT_EQ(mesh.tri().number_of_vertices(), 0u);
    EXPECT_EQ(mesh.tri().number_of_faces(), 0u);
    for (std::size_t f = 0; f < outlines.size(); ++f) {
        const std::string after = outlines[f].polygonal ? to_wkt(detail::assemble_boundary(mesh, boundary[f], eo))
                                                     : to_wkt(detail::extract_lines(mesh, lines.of(f), starts(f), eo));
        EXPECT_EQ(after, live[f]) << "feature " << f;
    }
}

// Mesh::insert_points puts the points in without CGAL's bookkeeping of constraint flags (there
// are none yet), with its own copy of CGAL's flips (BuildFlips). The triangulation must still be
// CGAL's constrained Delaunay one once the edges are in: CGAL's own check (every unconstrained
// edge locally Delaunay, the data structure sound), on inputs full of co-circular points (an
// exact grid, points exactly on circles), crossing squares and a jittered coverage.
TEST(MeshBuild, TheBuiltTriangulationIsConstrainedDelaunay)
{
    const double t = 1e-6;
    std::vector<std::pair<std::string, std::vector<Feature>>> inputs;
    inputs.emplace_back("exact grid", perturbed_grid_coverage(40, 40, 1.0, 0.0, 1));
    inputs.emplace_back("circles", std::vector<Feature>{circle(1, 2000, 10.0, 0.0, 2), circle(2, 500, 3.0, 0.0, 3)});
    inputs.emplace_back("crossing squares", random_small_squares(3000, 1.0, 60.0, 4));
    inputs.emplace_back("jittered coverage", perturbed_grid_coverage(30, 30, 1.0, 0.2, 5, 3));
    for (const auto& [name, in] : inputs) {
        std::vector<Problem> problems;
        const std::vector<detail::CleanFeature> clean = detail::clean_input(in, t, problems);
        detail::Mesh mesh(clean, t);
        EXPECT_GT(mesh.tri().number_of_faces(), 2000u) << name;
        EXPECT_TRUE(mesh.tri().is_valid()) << name;
    }
}

} // namespace
} // namespace trisnap
