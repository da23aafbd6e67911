// The GeoPackage spatial index the writer bulk loads (io/gpkg_rtree.hpp): the packing on its own,
// then written files checked by SQLite's rtreecheck() and queried through GDAL beside an index
// GDAL built itself, also after edits through GDAL (the triggers) and on the fallback path.
#include "io/gpkg_rtree.hpp"
#include "io/writer.hpp"
#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <set>

namespace trisnap {
namespace {

RtreeEntry box(std::int64_t id, double x, double y, double w, double h)
{
    OGREnvelope e;
    e.MinX = x;
    e.MaxX = x + w;
    e.MinY = y;
    e.MaxY = y + h;
    return rtree_entry(id, e);
}

bool contains(const RtreeEntry& outer, const RtreeEntry& inner)
{
    return outer.min_x <= inner.min_x && outer.max_x >= inner.max_x && outer.min_y <= inner.min_y &&
           outer.max_y >= inner.max_y;
}

/// Walks the packed tree from the root: every leaf at depth 0, every inner cell the exact union
/// of its child's cells, every node's parent recorded, every id in exactly one leaf.
void check_tree(const PackedRtree& tree, const std::vector<RtreeEntry>& entries, std::size_t max_cells)
{
    ASSERT_FALSE(tree.nodes.empty());
    std::multiset<std::int64_t> ids;
    std::vector<int> seen(tree.nodes.size(), 0);
    std::vector<std::pair<std::size_t, int>> todo{{0, tree.depth}};
    while (!todo.empty()) {
        const auto [k, depth] = todo.back();
        todo.pop_back();
        ++seen[k];
        const auto& cells = tree.nodes[k];
        ASSERT_LE(cells.size(), max_cells);
        EXPECT_EQ(k >= tree.first_leaf, depth == 0) << "node " << k + 1;
        if (depth == 0) {
            for (const RtreeEntry& c : cells) {
                ids.insert(c.id);
            }
            continue;
        }
        for (const RtreeEntry& c : cells) {
            ASSERT_GE(c.id, 2);
            const auto child = static_cast<std::size_t>(c.id - 1);
            ASSERT_LT(child, tree.nodes.size());
            EXPECT_EQ(tree.parent[child], static_cast<std::int64_t>(k) + 1);
            ASSERT_FALSE(tree.nodes[child].empty()) << "no empty node below the root";
            RtreeEntry u = tree.nodes[child].front();
            for (const RtreeEntry& g : tree.nodes[child]) {
                EXPECT_TRUE(contains(c, g));
                u.min_x = std::min(u.min_x, g.min_x);
                u.max_x = std::max(u.max_x, g.max_x);
                u.min_y = std::min(u.min_y, g.min_y);
                u.max_y = std::max(u.max_y, g.max_y);
            }
            EXPECT_TRUE(contains(u, c)) << "the cell is the children's union, no larger";
            todo.emplace_back(child, depth - 1);
        }
    }
    for (std::size_t k = 0; k < seen.size(); ++k) {
        EXPECT_EQ(seen[k], 1) << "node " << k + 1 << " reached once from the root";
    }
    std::multiset<std::int64_t> expected;
    for (const RtreeEntry& e : entries) {
        expected.insert(e.id);
    }
    EXPECT_EQ(ids, expected);
}

TEST(PackRtree, EveryBoxIsInOneLeafAndEveryNodeInsideItsParent)
{
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> at(-180, 180);
    std::uniform_real_distribution<double> size(0, 0.5);
    for (const std::size_t max_cells : {std::size_t{51}, std::size_t{4}}) {
        for (const std::size_t n : {0, 1, 4, 5, 51, 52, 2601, 2602, 20000}) {
            std::vector<RtreeEntry> entries;
            for (std::size_t i = 0; i < n; ++i) {
                entries.push_back(box(static_cast<std::int64_t>(i * 1000003 + 11), at(rng), at(rng) / 2, size(rng), size(rng)));
            }
            const PackedRtree tree = pack_rtree(entries, max_cells);
            SCOPED_TRACE("n " + std::to_string(n) + ", " + std::to_string(max_cells) + " cells");
            check_tree(tree, entries, max_cells);
            const std::size_t leaves = n == 0 ? 1 : (n + max_cells - 1) / max_cells;
            EXPECT_LE(tree.nodes.size() - tree.first_leaf, leaves + static_cast<std::size_t>(std::ceil(std::sqrt(leaves))))
                << "leaves are full but for the last of each slice";
            EXPECT_EQ(tree.depth == 0, n <= max_cells);
        }
    }
}

TEST(PackRtree, BoxesBeyondAFloatsRangeArePacked)
{
    // Coordinates past +-3.4e38 (the engine takes up to 2^44 t): sides of +-infinity, and boxes
    // over both, whose centre is NaN (gpkg_rtree.cpp puts 0 in its place for the sorts; that
    // guard cannot be seen failing here: without it libstdc++ happened to sort these anyway).
    std::vector<RtreeEntry> entries;
    for (int i = 0; i < 400; ++i) {
        OGREnvelope e;
        e.MinX = i % 3 == 0 ? -1e308 : i;
        e.MaxX = i % 5 == 0 ? 1e308 : i + 1.0;
        e.MinY = i % 7 == 0 ? -1e300 : -i;
        e.MaxY = i % 2 == 0 ? 1e300 : -i + 1.0;
        entries.push_back(rtree_entry(i + 1, e));
    }
    check_tree(pack_rtree(entries, 51), entries, 51);
    check_tree(pack_rtree(entries, 4), entries, 4);
}

TEST(PackRtree, TheSameBoxesInAnotherOrderGiveTheSameTree)
{
    std::vector<RtreeEntry> entries;
    for (int i = 0; i < 3000; ++i) {
        entries.push_back(box(i, (i * 37) % 101, (i * 53) % 97, 1, 1)); // many equal centres
    }
    const PackedRtree a = pack_rtree(entries, 51);
    std::reverse(entries.begin(), entries.end());
    const PackedRtree b = pack_rtree(entries, 51);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (std::size_t k = 0; k < a.nodes.size(); ++k) {
        EXPECT_EQ(rtree_node_blob(a.nodes[k], a.depth, k == 0, 1228), rtree_node_blob(b.nodes[k], b.depth, k == 0, 1228));
    }
}

TEST(RtreeEntry, SidesAreRoundedOutwardsToTheNearestFloat)
{
    for (const double d : {0.1, -0.1, 0.5, 1.0 / 3.0, -2.0 / 3.0, 42.507282257, 1e-40, -1e-40, 3e38, -3e38}) {
        OGREnvelope e;
        e.MinX = e.MaxX = e.MinY = e.MaxY = d;
        const RtreeEntry r = rtree_entry(1, e);
        EXPECT_LE(static_cast<double>(r.min_x), d);
        EXPECT_GE(static_cast<double>(r.max_x), d);
        EXPECT_GT(static_cast<double>(std::nextafter(r.min_x, std::numeric_limits<float>::infinity())), d) << d;
        EXPECT_LT(static_cast<double>(std::nextafter(r.max_x, -std::numeric_limits<float>::infinity())), d) << d;
        if (static_cast<double>(static_cast<float>(d)) == d) {
            EXPECT_EQ(r.min_x, r.max_x) << "a float is kept as it is";
        }
    }
    OGREnvelope huge;
    huge.MinX = huge.MinY = -1e308;
    huge.MaxX = huge.MaxY = 1e308;
    const RtreeEntry r = rtree_entry(1, huge);
    EXPECT_LE(static_cast<double>(r.min_x), -1e308) << "beyond a float: -infinity, still outside";
    EXPECT_GE(static_cast<double>(r.max_y), 1e308);
}

TEST(RtreeNodeBlob, IsSQLitesLayout)
{
    RtreeEntry c;
    c.id = 0x0102030405060708;
    c.min_x = 1.0F;  // 3F800000
    c.max_x = -2.0F; // C0000000
    c.min_y = 0.5F;  // 3F000000
    c.max_y = 0.0F;
    const std::string blob = rtree_node_blob({c}, 3, true, 1228);
    ASSERT_EQ(blob.size(), 1228u);
    const std::string head("\x00\x03\x00\x01\x01\x02\x03\x04\x05\x06\x07\x08\x3f\x80\x00\x00\xc0\x00\x00\x00\x3f\x00\x00\x00"
                           "\x00\x00\x00\x00",
                           28);
    EXPECT_EQ(blob.substr(0, 28), head);
    EXPECT_EQ(blob.find_first_not_of('\0', 28), std::string::npos);
    EXPECT_EQ(rtree_node_blob({c}, 3, false, 1228).substr(0, 2), std::string("\0\0", 2)) << "depth in the root only";
}

// ---- written files ----

struct Source {
    GDALDatasetUniquePtr dataset;
    OGRLayer* layer = nullptr;
};

Source memory_source()
{
    GDALAllRegister();
    Source s;
    s.dataset.reset(GetGDALDriverManager()->GetDriverByName("Memory")->Create("", 0, 0, 0, GDT_Unknown, nullptr));
    s.layer = s.dataset->CreateLayer("parcels", nullptr, wkbPolygon, nullptr);
    OGRFieldDefn name("name", OFTString);
    s.layer->CreateField(&name);
    return s;
}

OGRGeometry* square(double x, double y, double side)
{
    auto* ring = new OGRLinearRing;
    ring->addPoint(x, y);
    ring->addPoint(x + side, y);
    ring->addPoint(x + side, y + side);
    ring->addPoint(x, y + side);
    ring->addPoint(x, y);
    auto* polygon = new OGRPolygon;
    polygon->addRingDirectly(ring);
    return polygon;
}

/// Writes n squares (FIDs sparse, one null and one empty geometry) to `path` through LayerWriter.
void write_squares(const std::string& path, int n, const std::vector<std::string>& lco, std::size_t index_boxes)
{
    Source s = memory_source();
    WriteOptions options;
    options.path = path;
    options.layer_options = lco;
    options.index_boxes = index_boxes;
    LayerWriter writer(options, *s.layer);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> at(0, 1000);
    OGRFeature feature(s.layer->GetLayerDefn());
    for (int i = 0; i < n; ++i) {
        const std::string name = std::to_string(i);
        feature.SetField(0, name.c_str());
        OGRGeometry* g = i == 5 ? nullptr : i == 6 ? new OGRPolygon : square(at(rng), at(rng), 0.5 + i % 7);
        ASSERT_EQ(writer.write(feature, 1000003LL * i + 1, g), "");
    }
    writer.commit();
}

std::string text(GDALDataset& ds, const std::string& sql)
{
    OGRLayer* result = ds.ExecuteSQL(sql.c_str(), nullptr, nullptr);
    std::string value = "<no result>";
    if (result != nullptr) {
        OGRFeatureUniquePtr row(result->GetNextFeature());
        value = row ? row->GetFieldAsString(0) : "<no row>";
        ds.ReleaseResultSet(result);
    }
    return value;
}

std::set<GIntBig> fids_in(OGRLayer& layer, double x0, double y0, double x1, double y1)
{
    layer.SetSpatialFilterRect(x0, y0, x1, y1);
    std::set<GIntBig> fids;
    for (auto& f : layer) {
        fids.insert(f->GetFID());
    }
    layer.SetSpatialFilter(nullptr);
    return fids;
}

GDALDatasetUniquePtr open(const std::string& path, bool update)
{
    return GDALDatasetUniquePtr(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | (update ? GDAL_OF_UPDATE : 0), nullptr, nullptr, nullptr));
}

/// The reference: the same squares written without an index, then GDAL's CreateSpatialIndex().
void write_gdal_reference(const std::string& path, int n)
{
    write_squares(path, n, {"SPATIAL_INDEX=NO"}, std::size_t{1} << 26);
    auto g = open(path, true);
    ASSERT_TRUE(g);
    EXPECT_EQ(text(*g, "SELECT count(*) FROM sqlite_master WHERE name LIKE 'rtree%'"), "0") << "NO is kept";
    g->ReleaseResultSet(g->ExecuteSQL("SELECT CreateSpatialIndex('parcels', 'geom')", nullptr, nullptr));
}

/// The file's index is sound (rtreecheck) and answers windows like the index GDAL builds.
void expect_index_like_gdals(const std::string& ours, const std::string& reference, int expected_rows)
{
    auto a = open(ours, false);
    auto b = open(reference, false);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(text(*a, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
    EXPECT_EQ(text(*a, "SELECT count(*) FROM rtree_parcels_geom"), std::to_string(expected_rows)) << "no null or empty";
    EXPECT_EQ(text(*a, "SELECT scope FROM gpkg_extensions WHERE extension_name = 'gpkg_rtree_index' AND "
                       "table_name = 'parcels' AND column_name = 'geom'"),
              "write-only");
    EXPECT_EQ(text(*a, "SELECT count(*) FROM sqlite_master WHERE type = 'trigger' AND name LIKE 'rtree_parcels_geom_%'"), "6");
    OGRLayer* la = a->GetLayer(0);
    OGRLayer* lb = b->GetLayer(0);
    EXPECT_TRUE(la->TestCapability(OLCFastSpatialFilter)) << "GDAL sees the index";
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> at(-10, 1010);
    for (int q = 0; q < 40; ++q) {
        const double x = at(rng);
        const double y = at(rng);
        const double w = q % 2 ? 3 : 60;
        const auto got = fids_in(*la, x, y, x + w, y + w);
        EXPECT_EQ(got, fids_in(*lb, x, y, x + w, y + w)) << "window " << x << " " << y << " " << w;
    }
}

TEST(GpkgIndex, TheWritersIndexPassesRtreecheckAndAnswersLikeGdals)
{
    test::ScratchDir dir;
    const std::string ours = (dir.path() / "ours.gpkg").string();
    const std::string gdal = (dir.path() / "gdal.gpkg").string();
    write_squares(ours, 3000, {}, std::size_t{1} << 26);
    write_gdal_reference(gdal, 3000);
    expect_index_like_gdals(ours, gdal, 2998);
}

TEST(GpkgIndex, EditsThroughGdalKeepTheIndexInStep)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "edited.gpkg").string();
    write_squares(path, 600, {"SPATIAL_INDEX=YES"}, std::size_t{1} << 26);
    {
        auto ds = open(path, true);
        ASSERT_TRUE(ds);
        OGRLayer* layer = ds->GetLayer(0);
        OGRFeatureUniquePtr added(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        added->SetGeometryDirectly(square(5000, 5000, 1));
        ASSERT_EQ(layer->CreateFeature(added.get()), OGRERR_NONE);
        ASSERT_EQ(layer->DeleteFeature(1), OGRERR_NONE);
        OGRFeatureUniquePtr moved(layer->GetFeature(1000003LL * 10 + 1));
        ASSERT_TRUE(moved);
        moved->SetGeometryDirectly(square(-5000, -5000, 1));
        ASSERT_EQ(layer->SetFeature(moved.get()), OGRERR_NONE);
        EXPECT_EQ(text(*ds, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
        EXPECT_EQ(fids_in(*layer, 4999, 4999, 5002, 5002), std::set<GIntBig>{added->GetFID()});
        EXPECT_EQ(fids_in(*layer, -5001, -5001, -4998, -4998), std::set<GIntBig>{1000003LL * 10 + 1});
        EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom WHERE id = 1"), "0") << "deleted";
        EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom"), "598");
    }
}

/// Each R-tree table's rows in order, as text.
std::string rtree_rows(const std::string& path)
{
    auto ds = open(path, false);
    if (!ds) {
        return "<cannot open>";
    }
    return text(*ds, "SELECT group_concat(nodeno || ':' || hex(data)) FROM rtree_parcels_geom_node") + "|" +
           text(*ds, "SELECT group_concat(nodeno || ':' || parentnode) FROM rtree_parcels_geom_parent") + "|" +
           text(*ds, "SELECT group_concat(rowid || ':' || nodeno) FROM rtree_parcels_geom_rowid");
}

// Above its box budget the writer sorts the boxes in runs on disk (here 100 boxes a run; the
// parent and rowid rows 25 a run, so their merges take more than one pass) and packs the same
// tree level by level: the file is the one the in-memory packing writes, byte for byte, and
// its scratch files are gone.
TEST(GpkgIndex, BeyondItsBoxBudgetTheSameTreeIsPackedOnDisk)
{
    test::ScratchDir dir;
    const std::string ours = (dir.path() / "spilled.gpkg").string();
    const std::string bulk = (dir.path() / "bulk.gpkg").string();
    const std::string gdal = (dir.path() / "gdal.gpkg").string();
    write_squares(ours, 8000, {}, 100);
    write_squares(bulk, 8000, {}, std::size_t{1} << 26);
    write_gdal_reference(gdal, 8000);
    expect_index_like_gdals(ours, gdal, 7998);
    const std::string rows = rtree_rows(ours);
    EXPECT_EQ(rows, rtree_rows(bulk));
    EXPECT_NE(rows, rtree_rows(gdal)) << "packed, not GDAL's insertions";
    std::ifstream a(ours, std::ios::binary);
    std::ifstream b(bulk, std::ios::binary);
    const std::string bytes_a((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
    const std::string bytes_b((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
    EXPECT_GT(bytes_a.size(), 100000u);
    EXPECT_TRUE(bytes_a == bytes_b) << "the same file under any box budget";
    std::size_t left = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir.path())) {
        left += entry.is_regular_file() ? 1 : 0;
    }
    EXPECT_EQ(left, 3u) << "only the three files written";
}

TEST(GpkgIndex, NoIndexWhenAskedForNone)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "none.gpkg").string();
    write_squares(path, 50, {"spatial_index=no"}, std::size_t{1} << 26);
    auto ds = open(path, false);
    ASSERT_TRUE(ds);
    EXPECT_EQ(text(*ds, "SELECT count(*) FROM sqlite_master WHERE name LIKE 'rtree%'"), "0");
    EXPECT_FALSE(ds->GetLayer(0)->TestCapability(OLCFastSpatialFilter));
    if (text(*ds, "SELECT count(*) FROM sqlite_master WHERE name = 'gpkg_extensions'") == "1") {
        EXPECT_EQ(text(*ds, "SELECT count(*) FROM gpkg_extensions WHERE extension_name = 'gpkg_rtree_index'"), "0");
    }
}

TEST(GpkgIndex, AnEmptyLayerGetsAnEmptyIndex)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "empty.gpkg").string();
    write_squares(path, 0, {}, std::size_t{1} << 26);
    auto ds = open(path, false);
    ASSERT_TRUE(ds);
    EXPECT_EQ(text(*ds, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
    EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom"), "0");
}

/// n squares written to a new GeoPackage through OGR without an index, then the index written
/// by a GpkgIndexBuilder.
void write_indexed_by_builder(const std::string& path, int n, std::size_t max_entries = std::size_t{1} << 26)
{
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    const char* no_index[] = {"SPATIAL_INDEX=NO", nullptr};
    OGRLayer* layer = ds->CreateLayer("parcels", nullptr, wkbPolygon, const_cast<char**>(no_index));
    GpkgIndexBuilder builder(max_entries);
    EXPECT_EQ(ds->StartTransaction(), OGRERR_NONE);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> at(0, 1000);
    for (int i = 0; i < n; ++i) {
        OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        f->SetFID(7LL * i + 3);
        f->SetGeometryDirectly(square(at(rng), at(rng), 0.25 + i % 5));
        EXPECT_EQ(layer->CreateFeature(f.get()), OGRERR_NONE);
        builder.add(f->GetFID(), f->GetGeometryRef());
    }
    builder.write(*ds, *layer, path, "");
    EXPECT_EQ(ds->CommitTransaction(), OGRERR_NONE);
}

// The R-tree's rows (_node: each node's blob, _rowid: each FID's leaf, _parent: each node's
// parent) go in bound to statements prepared on GDAL's SQLite connection, 128 rows a statement
// and the rest one by one (25,000 features: 195 full statements and 40 single rows for _rowid;
// 502 nodes). Every feature is in the index once, under a box that holds its geometry, and
// SQLite's rtreecheck() finds the three tables consistent (it fails when a row is missing).
TEST(GpkgIndex, EveryRowGoesInAcrossTheBatches)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "bound.gpkg").string();
    write_indexed_by_builder(path, 25000);
    auto ds = open(path, false);
    ASSERT_TRUE(ds);
    EXPECT_EQ(text(*ds, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
    EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom_rowid"), "25000");
    EXPECT_EQ(text(*ds, "SELECT min(rowid) || ' ' || max(rowid) FROM rtree_parcels_geom_rowid"), "3 174996");
    EXPECT_EQ(text(*ds, "SELECT (SELECT count(*) FROM rtree_parcels_geom_node) - (SELECT count(*) FROM rtree_parcels_geom_parent)"), "1");
    EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom r JOIN parcels p ON r.id = p.fid WHERE r.minx <= ST_MinX(p.geom) "
                        "AND r.maxx >= ST_MaxX(p.geom) AND r.miny <= ST_MinY(p.geom) AND r.maxy >= ST_MaxY(p.geom)"),
              "25000");
    // The index answers: a window around one square finds it.
    OGRFeatureUniquePtr some(ds->GetLayer(0)->GetFeature(7LL * 12345 + 3));
    ASSERT_TRUE(some);
    OGREnvelope box;
    some->GetGeometryRef()->getEnvelope(&box);
    EXPECT_EQ(fids_in(*ds->GetLayer(0), box.MinX, box.MinY, box.MaxX, box.MaxY).count(7LL * 12345 + 3), 1u);
}

// Without a scratch directory (the builder used alone), GDAL builds the index above the budget.
TEST(GpkgIndex, BeyondItsBoxBudgetWithoutScratchGdalBuildsTheIndex)
{
    test::ScratchDir dir;
    const std::string ours = (dir.path() / "fallback.gpkg").string();
    const std::string gdal = (dir.path() / "gdal.gpkg").string();
    write_indexed_by_builder(ours, 800, 100);
    auto ds = open(ours, false);
    ASSERT_TRUE(ds);
    EXPECT_EQ(text(*ds, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
    EXPECT_EQ(text(*ds, "SELECT count(*) FROM rtree_parcels_geom"), "800");
    // GDAL's insertions leave nodes part full; the packed tree's are full but the last of each slice.
    EXPECT_GT(std::stoi(text(*ds, "SELECT count(*) FROM rtree_parcels_geom_node")), 800 / 51 + 2);
}

// The writer thread's write (app/write_phase.cpp): the geometry is lent, not given. After each
// write the caller holds the very object it lent, unchanged, and the file and its index hold
// the features as written.
TEST(GpkgIndex, LentGeometriesComeBackAndAreWritten)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "lent.gpkg").string();
    Source s = memory_source();
    WriteOptions options;
    options.path = path;
    std::vector<std::unique_ptr<OGRGeometry>> kept;
    {
        LayerWriter writer(options, *s.layer);
        OGRFeature feature(s.layer->GetLayerDefn());
        for (int i = 0; i < 50; ++i) {
            feature.SetField(0, std::to_string(i).c_str());
            std::unique_ptr<OGRGeometry> g(square(10.0 * i, 0, 1 + i % 3));
            const OGRGeometry* lent = g.get();
            const std::unique_ptr<OGRGeometry> copy(g->clone());
            ASSERT_EQ(writer.write_lending(0, feature, i + 1, g), "");
            ASSERT_EQ(g.get(), lent) << "feature " << i << ": not the geometry lent";
            EXPECT_TRUE(g->Equals(copy.get())) << "feature " << i << ": changed by the write";
            kept.push_back(std::move(g));
        }
        writer.commit();
    }
    auto ds = open(path, false);
    ASSERT_TRUE(ds);
    OGRLayer* layer = ds->GetLayer(0);
    ASSERT_NE(layer, nullptr);
    EXPECT_EQ(layer->GetFeatureCount(), 50);
    for (auto& f : *layer) {
        const auto i = static_cast<std::size_t>(f->GetFID() - 1);
        ASSERT_LT(i, kept.size());
        EXPECT_TRUE(f->GetGeometryRef() != nullptr && f->GetGeometryRef()->Equals(kept[i].get())) << "FID " << f->GetFID();
    }
    EXPECT_EQ(text(*ds, "SELECT rtreecheck('rtree_parcels_geom')"), "ok");
    EXPECT_EQ(fids_in(*layer, 95, -1, 125, 5), (std::set<GIntBig>{11, 12, 13})); // i = 10, 11, 12
}

} // namespace
} // namespace trisnap
