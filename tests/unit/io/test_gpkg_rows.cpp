// A new GeoPackage layer's rows inserted through GDAL's connection (io/gpkg_rows.hpp): the same
// features written through LayerWriter twice, once as rows whose blobs encode_gpkg made (as the
// write phase does) and once through GDAL (WriteOptions::rows off), must give the same file but
// for SQLite's two header counters of write transactions. The features mix what the write phase
// meets: engine results (single and multi, holes, 2D and Z with a missing z, signed zeros on the
// box's sides, where only OGR's order of comparisons decides the bits), features passed
// through (a point, an empty polygon, no geometry, a curve that only GDAL writes), and fields
// set, null and unset.
#include "io/gpkg_rows.hpp"
#include "io/ogr_geometry.hpp"
#include "io/writer.hpp"
#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <sqlite3.h>

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <variant>

namespace trisnap {
namespace {

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

struct Source {
    GDALDatasetUniquePtr dataset;
    OGRLayer* layer = nullptr;
};

/// A source field (OGRFieldDefn cannot be copied).
struct Field {
    const char* name;
    OGRFieldType type;
    int width = 0;
    OGRFieldSubType subtype = OFSTNone;
    const char* default_value = nullptr;
};

/// A layer `name` of `type` (EPSG:28992) with `fields`, in `dataset`.
OGRLayer* add_layer(GDALDataset& dataset, const char* name, OGRwkbGeometryType type, const std::vector<Field>& fields)
{
    OGRSpatialReference srs;
    srs.importFromEPSG(28992);
    OGRLayer* layer = dataset.CreateLayer(name, &srs, type, nullptr);
    for (const Field& f : fields) {
        OGRFieldDefn d(f.name, f.type);
        d.SetWidth(f.width);
        d.SetSubType(f.subtype);
        d.SetDefault(f.default_value);
        layer->CreateField(&d);
    }
    return layer;
}

Source memory_source(OGRwkbGeometryType type, const std::vector<Field>& fields)
{
    GDALAllRegister();
    Source s;
    s.dataset.reset(GetGDALDriverManager()->GetDriverByName("Memory")->Create("", 0, 0, 0, GDT_Unknown, nullptr));
    s.layer = add_layer(*s.dataset, "parcels", type, fields);
    return s;
}

std::vector<Field> usual_fields()
{
    // "s" is 4 wide: longer values make GDAL warn, and it writes them whole.
    return {{"n", OFTInteger}, {"big", OFTInteger64}, {"r", OFTReal}, {"s", OFTString, 4}, {"flag", OFTInteger, 0, OFSTBoolean}};
}

Path ring(std::vector<std::array<double, 3>> points)
{
    Path p;
    for (const auto& [x, y, z] : points) {
        p.push_back({x, y, z});
    }
    p.push_back(p.front());
    return p;
}

/// One feature to write: an engine result (snapped) or an OGR geometry (passed through, may be null).
struct Item {
    std::int64_t fid = 0;
    std::variant<Geometry, std::shared_ptr<OGRGeometry>> geometry;
    OGRwkbGeometryType like = wkbPolygon;
};

Geometry polygons(bool z, std::vector<Polygon> parts)
{
    Geometry g;
    g.type = parts.size() == 1 ? Geometry::Type::Polygon : Geometry::Type::MultiPolygon;
    g.polygons = std::move(parts);
    g.has_z = z;
    return g;
}

Geometry lines(bool z, std::vector<Path> parts)
{
    Geometry g;
    g.type = parts.size() == 1 ? Geometry::Type::LineString : Geometry::Type::MultiLineString;
    g.lines = std::move(parts);
    g.has_z = z;
    return g;
}

std::shared_ptr<OGRGeometry> wkt(const char* text)
{
    OGRGeometry* g = nullptr;
    EXPECT_EQ(OGRGeometryFactory::createFromWkt(text, nullptr, &g), OGRERR_NONE) << text;
    return std::shared_ptr<OGRGeometry>(g);
}

/// Polygonal results, 2D and Z, with what decides a blob's bits.
std::vector<Item> polygonal_items(bool z)
{
    std::vector<Item> items;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> at(-500, 500);
    for (int i = 0; i < 40; ++i) {
        const double x = at(rng), y = at(rng), s = 1 + i % 5;
        const double zz = z ? (i % 3 == 0 ? k_nan : at(rng)) : k_nan; // a missing z is written as 0
        Polygon a{{ring({{x, y, zz}, {x + s, y, 1}, {x + s, y + s, -2}, {x, y + s, zz}})}};
        if (i % 4 == 1) {
            a.rings.push_back(ring({{x + 0.2, y + 0.2, 3}, {x + 0.2, y + 0.6, 3}, {x + 0.6, y + 0.2, 3}}));
        }
        std::vector<Polygon> parts{a};
        if (i % 3 == 2) {
            parts.push_back(Polygon{{ring({{x + 10, y, 0}, {x + 11, y, 0}, {x + 11, y + 1, 0}})}});
        }
        items.push_back({1000 + 7 * i, polygons(z, parts), i % 2 ? wkbMultiPolygon : wkbPolygon});
    }
    // Signed zeros on every side of the box, in both orders: within a ring the first of equal
    // values stays, across rings and parts the later one (OGREnvelope::Merge).
    Polygon zeros{{ring({{0.0, -0.0, 0.0}, {1, -0.0, 0.0}, {1, 1, -0.0}, {-0.0, 0.0, -0.0}})}};
    zeros.rings.push_back(ring({{0.0, 0.0, 0.0}, {0.0, 0.5, -0.0}, {-0.0, 0.0, 0.0}}));
    Polygon zeros2{{ring({{-0.0, -0.0, -0.0}, {2, 0.0, 0.0}, {2, 2, 0.0}})}};
    items.push_back({1, polygons(z, {zeros}), wkbPolygon});
    items.push_back({2, polygons(z, {zeros, zeros2}), wkbMultiPolygon});
    items.push_back({3, polygons(z, {zeros2, zeros}), wkbMultiPolygon});
    {   // a heavy row (3,000 vertices, ~48 KB): the queue goes in row by row (GpkgRows::k_batch_bytes)
        std::vector<std::array<double, 3>> circle;
        for (int i = 0; i < 3000; ++i) {
            const double a = 2 * M_PI * i / 3000;
            circle.push_back({700 + 50 * std::cos(a), 700 + 50 * std::sin(a), z ? 1.0 * i : k_nan});
        }
        items.push_back({13, polygons(z, {Polygon{{ring(circle)}}}), wkbPolygon});
    }
    items.push_back({4, Geometry{}, wkbPolygon}); // vanished: not written by the write phase; here a null geometry
    items.push_back({5, wkt("POINT (3 4)"), wkbPoint});
    items.push_back({6, wkt("POLYGON EMPTY"), wkbPolygon});
    items.push_back({7, std::shared_ptr<OGRGeometry>(), wkbPolygon});
    items.push_back({8, wkt("CURVEPOLYGON (CIRCULARSTRING (0 0,1 1,2 0,1 -1,0 0))"), wkbCurvePolygon});
    items.push_back({9, wkt("MULTIPOINT Z ((1 2 3),(4 5 6))"), wkbMultiPoint});
    items.push_back({10, wkt("GEOMETRYCOLLECTION (POINT (1 2),LINESTRING (0 0,1 1))"), wkbGeometryCollection});
    items.push_back({11, wkt("LINESTRING M (0 0 5,1 1 6)"), wkbLineString});
    items.push_back({12, wkt("POINT EMPTY"), wkbPoint});
    return items;
}

std::vector<Item> lineal_items(bool z)
{
    std::vector<Item> items;
    for (int i = 0; i < 20; ++i) {
        const double x = i * 3.5 - 20;
        Path a{{x, 1, z ? 4.0 : k_nan}, {x + 1, 2, k_nan}, {x + 2, -0.0, 7}};
        Path b{{x, -5, 1}, {x - 1, 0.0, 2}};
        items.push_back({100 + i, i % 2 ? lines(z, {a, b}) : lines(z, {a}), i % 3 ? wkbLineString : wkbMultiLineString});
    }
    return items;
}

/// The feature's attributes: set, null and unset in turn, long strings among them.
void fill(OGRFeature& f, std::int64_t fid)
{
    const int k = static_cast<int>(fid % 5);
    f.UnsetField(0);
    f.UnsetField(1);
    f.UnsetField(2);
    f.UnsetField(3);
    f.UnsetField(4);
    if (k != 1) f.SetField(0, static_cast<int>(fid * 3 - 100));
    if (k == 1) f.SetFieldNull(0);
    if (k != 2) f.SetField(1, static_cast<GIntBig>(fid) * 123456789012LL);
    if (k != 3) f.SetField(2, k == 4 ? std::nan("") : fid / 7.0);
    if (k == 3) f.SetFieldNull(2);
    if (k != 4) f.SetField(3, k == 0 ? "short" : "a much longer value than the width \xc3\xa9");
    f.SetField(4, k % 2);
}

/// An engine result written as the write phase writes it into a layer that takes rows: its blob
/// encoded, the feature's values taken, the row queued.
void write_as_row(LayerWriter& writer, std::size_t k, const OGRFeature& f, std::int64_t fid, const Geometry& g,
                  OGRwkbGeometryType like)
{
    GpkgGeometry blob;
    GpkgValues values;
    encode_gpkg(g, like, writer.rows(k)->srs_id(), blob);
    writer.rows(k)->take(f, fid, values);
    writer.write_row(k, values, blob);
}

/// Writes `items` to `path` as the write phase would: rows where the layer takes them.
void write_items(const std::string& path, OGRwkbGeometryType type, const std::vector<Item>& items, bool rows,
                 bool renumber, bool* took_rows = nullptr, bool overwrite = false)
{
    Source s = memory_source(type, usual_fields());
    WriteOptions options;
    options.path = path;
    options.rows = rows;
    options.renumber = {renumber};
    options.overwrite = overwrite;
    LayerWriter writer(options, *s.layer);
    if (took_rows != nullptr) {
        *took_rows = writer.rows(0) != nullptr;
    }
    OGRFeature f(s.layer->GetLayerDefn());
    for (const Item& item : items) {
        fill(f, item.fid);
        const GpkgRows* r = writer.rows(0);
        GpkgGeometry blob;
        std::string error;
        if (const auto* g = std::get_if<Geometry>(&item.geometry)) {
            if (r != nullptr) {
                write_as_row(writer, 0, f, item.fid, *g, item.like);
            } else {
                error = writer.write(0, f, item.fid, to_ogr(*g, item.like));
            }
        } else {
            const auto& o = std::get<std::shared_ptr<OGRGeometry>>(item.geometry);
            if (r != nullptr && encode_gpkg(o.get(), r->srs_id(), blob)) {
                GpkgValues values;
                r->take(f, item.fid, values);
                writer.write_row(0, values, blob);
            } else {
                error = writer.write(0, f, item.fid, o ? o->clone() : nullptr);
            }
        }
        ASSERT_EQ(error, "") << "FID " << item.fid;
    }
    writer.commit();
    EXPECT_TRUE(writer.take_refusals().empty());
    EXPECT_EQ(writer.written(), items.size());
}

std::string bytes_of(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The offsets where two files differ, SQLite's file change counter (24..27) and
/// version-valid-for number (92..95) aside.
std::vector<std::size_t> differences(const std::string& a, const std::string& b)
{
    const std::string x = bytes_of(a);
    const std::string y = bytes_of(b);
    std::vector<std::size_t> at;
    if (x.size() != y.size()) {
        return {std::max(x.size(), y.size())};
    }
    for (std::size_t i = 0; i < x.size() && at.size() < 10; ++i) {
        if (x[i] != y[i] && !(i >= 24 && i < 28) && !(i >= 92 && i < 96)) {
            at.push_back(i);
        }
    }
    return at;
}

std::string query(const std::string& path, const std::string& sql)
{
    sqlite3* db = nullptr;
    sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
    sqlite3_stmt* st = nullptr;
    std::string out = "<error>";
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr) == SQLITE_OK) {
        out.clear();
        while (sqlite3_step(st) == SQLITE_ROW) {
            for (int c = 0; c < sqlite3_column_count(st); ++c) {
                const unsigned char* t = sqlite3_column_text(st, c);
                if (c > 0) {
                    out += '|';
                }
                out += t ? reinterpret_cast<const char*>(t) : "NULL";
            }
            out += ";";
        }
    }
    sqlite3_finalize(st);
    sqlite3_close(db);
    return out;
}

void expect_same_file(OGRwkbGeometryType type, const std::vector<Item>& items, bool renumber)
{
    test::ScratchDir dir;
    const std::string rows = (dir.path() / "rows.gpkg").string();
    const std::string gdal = (dir.path() / "gdal.gpkg").string();
    bool took = false;
    write_items(rows, type, items, true, renumber, &took);
    write_items(gdal, type, items, false, renumber);
    EXPECT_TRUE(took) << "the layer takes rows";
    EXPECT_EQ(differences(rows, gdal), std::vector<std::size_t>{});
    // Not two empty files: every feature is there, with the count and extent GDAL keeps.
    EXPECT_EQ(query(rows, "SELECT count(*) FROM parcels"), std::to_string(items.size()) + ";");
    EXPECT_EQ(query(rows, "SELECT feature_count FROM gpkg_ogr_contents"), std::to_string(items.size()) + ";");
    EXPECT_NE(query(rows, "SELECT min_x FROM gpkg_contents WHERE table_name = 'parcels'"), "NULL;");
}

TEST(GpkgRows, PolygonsAreGdalsRowsByteForByte)
{
    expect_same_file(wkbMultiPolygon, polygonal_items(false), false);
}

TEST(GpkgRows, PolygonsWithZAreGdalsRowsByteForByte)
{
    expect_same_file(wkbPolygon25D, polygonal_items(true), false);
}

TEST(GpkgRows, LinesAreGdalsRowsByteForByte)
{
    expect_same_file(wkbMultiLineString, lineal_items(false), false);
    expect_same_file(wkbLineString25D, lineal_items(true), false);
}

TEST(GpkgRows, RenumberedFeaturesKeepTheirFidInOrigFid)
{
    expect_same_file(wkbMultiPolygon, polygonal_items(false), true);
    test::ScratchDir dir;
    const std::string path = (dir.path() / "r.gpkg").string();
    write_items(path, wkbMultiPolygon, lineal_items(false), true, true);
    EXPECT_EQ(query(path, "SELECT fid, orig_fid FROM parcels ORDER BY fid LIMIT 2"), "1|100;2|101;");
}

TEST(GpkgRows, BlobsDecodeToTheGeometriesGiven)
{
    const Geometry g = polygons(true, {Polygon{{ring({{0, 0, 1}, {4, 0, k_nan}, {4, 3, 2}})}}});
    GpkgGeometry blob;
    encode_gpkg(g, wkbMultiPolygon, 28992, blob);
    ASSERT_TRUE(blob.boxed);
    EXPECT_EQ(blob.box.MinX, 0);
    EXPECT_EQ(blob.box.MaxX, 4);
    EXPECT_EQ(blob.box.MaxY, 3);
    ASSERT_GT(blob.blob.size(), 8 + 48u);
    EXPECT_EQ(blob.blob.substr(0, 2), "GP");
    EXPECT_EQ(static_cast<unsigned char>(blob.blob[3]), (2 << 1) | 1) << "an XYZ envelope, little-endian";
    OGRGeometry* back = nullptr;
    ASSERT_EQ(OGRGeometryFactory::createFromWkb(blob.blob.data() + 8 + 48, nullptr, &back, blob.blob.size() - 56),
              OGRERR_NONE);
    std::unique_ptr<OGRGeometry> owned(back);
    char* text = nullptr;
    back->exportToWkt(&text, wkbVariantIso);
    EXPECT_STREQ(text, "MULTIPOLYGON Z (((0 0 1,4 0 0,4 3 2,0 0 1)))");
    CPLFree(text);
    encode_gpkg(Geometry{}, wkbPolygon, 28992, blob);
    EXPECT_TRUE(blob.blob.empty()) << "no geometry: a null one";
    EXPECT_FALSE(blob.boxed);
}

TEST(GpkgRows, CurvesAndSurfacesAreLeftToGdal)
{
    GpkgGeometry blob;
    blob.blob = "kept";
    EXPECT_FALSE(encode_gpkg(wkt("CIRCULARSTRING (0 0,1 1,2 0)").get(), 0, blob));
    EXPECT_FALSE(encode_gpkg(wkt("GEOMETRYCOLLECTION (POINT (1 2),CIRCULARSTRING (0 0,1 1,2 0))").get(), 0, blob));
    EXPECT_FALSE(encode_gpkg(wkt("TIN (((0 0 0,0 1 0,1 1 0,0 0 0)))").get(), 0, blob));
    EXPECT_EQ(blob.blob, "kept") << "untouched when refused";
    EXPECT_TRUE(encode_gpkg(wkt("GEOMETRYCOLLECTION (POINT (1 2),LINESTRING (0 0,1 1))").get(), 0, blob));
    EXPECT_TRUE(encode_gpkg(nullptr, 0, blob));
    EXPECT_TRUE(blob.blob.empty());
}

/// A layer GDAL writes differently from what the rows do: no rows, every feature through GDAL.
void expect_no_rows(OGRwkbGeometryType type, const std::vector<Field>& fields, std::vector<std::string> lco)
{
    test::ScratchDir dir;
    Source s = memory_source(type, fields);
    WriteOptions options;
    options.path = (dir.path() / "o.gpkg").string();
    options.layer_options = lco;
    LayerWriter writer(options, *s.layer);
    EXPECT_EQ(writer.rows(0), nullptr);
    OGRFeature f(s.layer->GetLayerDefn());
    EXPECT_EQ(writer.write(0, f, 1, wkt("POLYGON ((0 0,1 0,1 1,0 0))")->clone()), "");
    writer.commit();
    EXPECT_EQ(query(options.path, "SELECT count(*) FROM parcels"), "1;");
}

TEST(GpkgRows, NotForLayersGdalWritesOtherwise)
{
    expect_no_rows(wkbUnknown, {}, {}); // GDAL edits gpkg_geometry_columns as geometries come
    expect_no_rows(wkbPolygon, {{"day", OFTDate}}, {});
    expect_no_rows(wkbPolygon, {{"bytes", OFTBinary}}, {});
    expect_no_rows(wkbPolygon, {{"n", OFTInteger, 0, OFSTNone, "7"}}, {}); // GDAL fills unset fields with it
    expect_no_rows(wkbPolygon, {{"s", OFTString, 2}}, {"TRUNCATE_FIELDS=YES"});
    expect_no_rows(wkbCurvePolygon, {}, {});
}

/// Writes `fids` (square polygons) one way; returns what was refused (FID: message), the count
/// written, and the rows as text.
struct Written {
    std::vector<std::pair<std::int64_t, std::string>> refused;
    std::size_t written = 0;
    std::string rows;
};

Written write_fids(const std::string& path, const std::vector<std::int64_t>& fids, bool rows)
{
    Written w;
    Source s = memory_source(wkbPolygon, usual_fields());
    WriteOptions options;
    options.path = path;
    options.rows = rows;
    LayerWriter writer(options, *s.layer);
    EXPECT_EQ(writer.rows(0) != nullptr, rows);
    OGRFeature f(s.layer->GetLayerDefn());
    for (const std::int64_t fid : fids) {
        fill(f, fid);
        const double x = static_cast<double>(fid % 97);
        const Geometry g = polygons(false, {Polygon{{ring({{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}})}}});
        if (rows) {
            write_as_row(writer, 0, f, fid, g, wkbPolygon);
        } else if (std::string error = writer.write(0, f, fid, to_ogr(g, wkbPolygon)); !error.empty()) {
            w.refused.emplace_back(fid, error);
        }
    }
    if (rows) {
        writer.flush_rows();
        for (const LayerWriter::Refusal& r : writer.take_refusals()) {
            EXPECT_EQ(r.layer, 0u);
            w.refused.emplace_back(r.fid, r.message);
        }
    }
    w.written = writer.written();
    writer.commit();
    EXPECT_TRUE(writer.take_refusals().empty()) << "all of them taken before the commit";
    w.rows = query(path, "SELECT fid, hex(geom), n, big, r, s, flag FROM parcels ORDER BY fid");
    return w;
}

TEST(GpkgRows, ARefusedRowIsReportedAsGdalReportsIt)
{
    // FID 5 twice: the primary key refuses the second, alone in its (short) batch.
    test::ScratchDir dir;
    const Written gdal = write_fids((dir.path() / "g.gpkg").string(), {5, 5}, false);
    const Written rows = write_fids((dir.path() / "r.gpkg").string(), {5, 5}, true);
    ASSERT_EQ(gdal.refused.size(), 1u);
    EXPECT_NE(gdal.refused[0].second, "");
    EXPECT_EQ(rows.refused, gdal.refused);
    EXPECT_EQ(rows.written, 1u);
    EXPECT_EQ(query((dir.path() / "r.gpkg").string(), "SELECT feature_count FROM gpkg_ogr_contents"), "1;");
}

TEST(GpkgRows, ARefusedRowInAFullBatchLeavesTheOthersIn)
{
    // 50 features, FID 20 repeated as the 30th: the second batch of 16 is refused as a whole,
    // then goes in row by row; the other 49 are written, in order, as GDAL writes them.
    std::vector<std::int64_t> fids;
    for (std::int64_t i = 0; i < 50; ++i) {
        fids.push_back(i == 29 ? 20 : i + 1);
    }
    test::ScratchDir dir;
    const Written gdal = write_fids((dir.path() / "g.gpkg").string(), fids, false);
    const Written rows = write_fids((dir.path() / "r.gpkg").string(), fids, true);
    ASSERT_EQ(gdal.refused.size(), 1u);
    EXPECT_EQ(gdal.refused[0].first, 20);
    EXPECT_EQ(rows.refused, gdal.refused);
    EXPECT_EQ(rows.written, 49u);
    EXPECT_EQ(gdal.written, 49u);
    EXPECT_EQ(rows.rows, gdal.rows);
    EXPECT_EQ(query((dir.path() / "r.gpkg").string(), "SELECT feature_count FROM gpkg_ogr_contents"), "49;");
    EXPECT_EQ(query((dir.path() / "r.gpkg").string(), "SELECT count(*) FROM rtree_parcels_geom"), "49;");
}

TEST(GpkgRows, SeveralLayersInOneFileHoldGdalsRows)
{
    // Two layers into one OUT, written one after the other as the write phase does. Their tables
    // are created up front (GDAL creates the second at its first feature), so the pages are laid
    // out otherwise: the rows, extents and counts are GDAL's.
    std::string dumps[2];
    test::ScratchDir dir;
    for (int rows = 0; rows < 2; ++rows) {
        GDALAllRegister();
        GDALDatasetUniquePtr memory(GetGDALDriverManager()->GetDriverByName("Memory")->Create("", 0, 0, 0, GDT_Unknown, nullptr));
        std::vector<OGRLayer*> sources;
        for (const char* name : {"parcels", "roads"}) {
            sources.push_back(add_layer(*memory, name, wkbPolygon, usual_fields()));
        }
        WriteOptions options;
        options.path = (dir.path() / (rows ? "r.gpkg" : "g.gpkg")).string();
        options.rows = rows == 1;
        LayerWriter writer(options, sources);
        for (std::size_t k = 0; k < 2; ++k) {
            ASSERT_EQ(writer.rows(k) != nullptr, rows == 1);
            OGRFeature f(sources[k]->GetLayerDefn());
            for (std::int64_t fid = 1; fid <= 37; ++fid) {
                fill(f, fid);
                const double x = static_cast<double>(fid) + 100.0 * static_cast<double>(k);
                const Geometry g = polygons(false, {Polygon{{ring({{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}})}}});
                if (rows == 1) {
                    write_as_row(writer, k, f, fid, g, wkbPolygon);
                } else {
                    ASSERT_EQ(writer.write(k, f, fid, to_ogr(g, wkbPolygon)), "");
                }
            }
        }
        writer.commit();
        EXPECT_TRUE(writer.take_refusals().empty());
        EXPECT_EQ(writer.written(0), 37u);
        EXPECT_EQ(writer.written(1), 37u);
        for (const char* table : {"parcels", "roads"}) {
            dumps[rows] += query(options.path, std::string("SELECT fid, hex(geom), n, big, r, s, flag FROM ") + table + " ORDER BY fid");
        }
        dumps[rows] += query(options.path, "SELECT table_name, min_x, min_y, max_x, max_y FROM gpkg_contents ORDER BY table_name");
        dumps[rows] += query(options.path, "SELECT * FROM gpkg_ogr_contents ORDER BY table_name");
        dumps[rows] += query(options.path, "SELECT count(*) FROM rtree_roads_geom");
    }
    EXPECT_NE(dumps[0].find("roads|37;"), std::string::npos) << dumps[0];
    EXPECT_EQ(dumps[1], dumps[0]);
}

/// An existing OUT as GDAL writes it: "parcels" (the layer the writer replaces) and "keep",
/// three features each.
void existing_out(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(ds);
    for (const char* name : {"parcels", "keep"}) {
        OGRLayer* layer = add_layer(*ds, name, wkbPolygon, usual_fields());
        OGRFeature f(layer->GetLayerDefn());
        for (std::int64_t fid = 1; fid <= 3; ++fid) {
            fill(f, fid);
            f.SetFID(fid);
            const double x = 1000.0 + static_cast<double>(fid);
            f.SetGeometryDirectly(to_ogr(polygons(false, {Polygon{{ring({{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}})}}}), wkbPolygon));
            ASSERT_EQ(layer->CreateFeature(&f), OGRERR_NONE);
        }
    }
}

std::string dump_out(const std::string& path)
{
    std::string d;
    for (const char* table : {"parcels", "keep"}) {
        d += query(path, std::string("SELECT fid, hex(geom), n, big, r, s, flag FROM ") + table + " ORDER BY fid");
        d += query(path, std::string("SELECT * FROM rtree_") + table + "_geom ORDER BY id");
    }
    d += query(path, "SELECT table_name, min_x, min_y, max_x, max_y FROM gpkg_contents ORDER BY table_name");
    d += query(path, "SELECT * FROM gpkg_ogr_contents ORDER BY table_name");
    d += query(path, "SELECT type, name, sql FROM sqlite_master ORDER BY type, name");
    return d;
}

// --overwrite of a layer in an existing GeoPackage (in place, in the transaction the writer
// opens) takes rows as a new OUT does: the file then holds what GDAL's path leaves (the rows,
// their index, the extent, the counts, the schema), and the other layer is untouched.
TEST(GpkgRows, AnOverwrittenLayerInAnExistingFileHoldsGdalsRows)
{
    test::ScratchDir dir;
    std::string dumps[2];
    std::string keep_before;
    for (int rows = 0; rows < 2; ++rows) {
        const std::string path = (dir.path() / (rows ? "r.gpkg" : "g.gpkg")).string();
        existing_out(path);
        keep_before = query(path, "SELECT fid, hex(geom), n, big, r, s, flag FROM keep ORDER BY fid");
        bool took = false;
        write_items(path, wkbPolygon, polygonal_items(false), rows == 1, false, &took, true);
        EXPECT_EQ(took, rows == 1);
        dumps[rows] = dump_out(path);
        EXPECT_EQ(query(path, "SELECT fid, hex(geom), n, big, r, s, flag FROM keep ORDER BY fid"), keep_before);
        EXPECT_EQ(query(path, "SELECT count(*) FROM parcels"), std::to_string(polygonal_items(false).size()) + ";");
    }
    EXPECT_NE(keep_before.find("3|"), std::string::npos) << keep_before;
    EXPECT_EQ(dumps[1], dumps[0]);
}

// A writer in place that stops before its commit (a failure, an interrupt) leaves the existing
// file as it was: the rows went into its transaction, which is rolled back.
TEST(GpkgRows, RowsInPlaceAreRolledBackWithoutACommit)
{
    test::ScratchDir dir;
    const std::string path = (dir.path() / "out.gpkg").string();
    existing_out(path);
    const std::string before = dump_out(path);
    {
        Source s = memory_source(wkbPolygon, usual_fields());
        WriteOptions options;
        options.path = path;
        options.overwrite = true;
        LayerWriter writer(options, *s.layer);
        ASSERT_NE(writer.rows(0), nullptr) << "the replaced layer takes rows";
        OGRFeature f(s.layer->GetLayerDefn());
        for (const Item& item : polygonal_items(false)) {
            const auto* g = std::get_if<Geometry>(&item.geometry);
            if (g == nullptr) {
                continue; // passed through: GDAL's path
            }
            fill(f, item.fid);
            write_as_row(writer, 0, f, item.fid, *g, item.like);
        }
        writer.flush_rows(); // the rows are in the file's transaction, not only in the batch
    }
    EXPECT_EQ(dump_out(path), before);
}

} // namespace
} // namespace trisnap
