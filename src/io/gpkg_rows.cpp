#include "io/gpkg_rows.hpp"

#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"

#include <cpl_string.h>
#include <sqlite3.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace trisnap {
namespace {

// GDAL writes blobs in the host's byte order (CPL_IS_LSB), and says which in the flags byte and
// in each WKB geometry's first byte: 1 little-endian (wkbNDR), 0 big-endian.
constexpr unsigned char k_byte_order = std::endian::native == std::endian::little ? 1 : 0;
constexpr std::uint32_t k_iso_z = 1000; // ISO WKB: a type with Z is the 2D type + 1000

// OGREnvelope::Merge's MIN and MAX (cpl_port.h): on a tie the second operand. Only signed zeros
// tell the difference, and the blobs must be GDAL's to the bit.
double merged_min(double a, double b) { return a < b ? a : b; }
double merged_max(double a, double b) { return a > b ? a : b; }

/// An XYZ box built as OGR builds a geometry's: each path's box from its first point on (the
/// first of equal values kept), the paths' boxes merged in order (OGREnvelope3D::Merge).
struct Box3 {
    double min_x = std::numeric_limits<double>::infinity(), max_x = -std::numeric_limits<double>::infinity();
    double min_y = min_x, max_y = max_x, min_z = min_x, max_z = max_x;

    void merge_path(const Path& path)
    {
        const Coord& first = path.front();
        Box3 b;
        b.min_x = b.max_x = first.x;
        b.min_y = b.max_y = first.y;
        b.min_z = b.max_z = z_of(first);
        for (std::size_t i = 1; i < path.size(); ++i) {
            const Coord& c = path[i];
            if (b.max_x < c.x) b.max_x = c.x;
            if (b.max_y < c.y) b.max_y = c.y;
            if (b.min_x > c.x) b.min_x = c.x;
            if (b.min_y > c.y) b.min_y = c.y;
            const double z = z_of(c);
            if (b.min_z > z) b.min_z = z;
            if (b.max_z < z) b.max_z = z;
        }
        min_x = merged_min(min_x, b.min_x);
        max_x = merged_max(max_x, b.max_x);
        min_y = merged_min(min_y, b.min_y);
        max_y = merged_max(max_y, b.max_y);
        min_z = merged_min(min_z, b.min_z);
        max_z = merged_max(max_z, b.max_z);
    }
    /// The z to_ogr writes: none (NaN) becomes 0.
    static double z_of(const Coord& c) { return std::isnan(c.z) ? 0.0 : c.z; }
};

/// Appends values in the host's byte order, as GDAL's exportToWkb(CPL_IS_LSB) does.
class Bytes {
public:
    explicit Bytes(std::string& out) : m_out(out) {}
    void u8(unsigned char v) { m_out.push_back(static_cast<char>(v)); }
    void u32(std::uint32_t v) { raw(&v, sizeof v); }
    void i32(std::int32_t v) { raw(&v, sizeof v); }
    void f64(double v) { raw(&v, sizeof v); }
    void header(std::uint32_t type)
    {
        u8(k_byte_order);
        u32(type);
    }
    void path(const Path& p, bool z)
    {
        u32(static_cast<std::uint32_t>(p.size()));
        for (const Coord& c : p) {
            f64(c.x);
            f64(c.y);
            if (z) {
                f64(Box3::z_of(c));
            }
        }
    }
    void polygon(const Polygon& p, bool z)
    {
        header(wkbPolygon + (z ? k_iso_z : 0));
        u32(static_cast<std::uint32_t>(p.rings.size()));
        for (const Path& ring : p.rings) {
            path(ring, z);
        }
    }
    void line(const Path& l, bool z)
    {
        header(wkbLineString + (z ? k_iso_z : 0));
        path(l, z);
    }

private:
    void raw(const void* v, std::size_t n) { m_out.append(static_cast<const char*>(v), n); }
    std::string& m_out;
};

std::size_t path_bytes(const Path& p, bool z) { return 4 + p.size() * (z ? 24 : 16); }

std::size_t polygon_bytes(const Polygon& p, bool z)
{
    std::size_t n = 9;
    for (const Path& ring : p.rings) {
        n += path_bytes(ring, z);
    }
    return n;
}

/// GPkgGeometryFromOGR's header: magic, version 0, flags, srs_id, the envelope (XY or XYZ;
/// none for points and empty geometries).
void put_header(Bytes& out, std::int32_t srs_id, bool point, bool empty, int dims, const Box3& box)
{
    const bool enveloped = !point && !empty;
    const unsigned char envelope = enveloped ? (dims == 3 ? 2 : 1) : 0;
    out.u8(0x47);
    out.u8(0x50);
    out.u8(0);
    out.u8(static_cast<unsigned char>((empty ? 1 << 4 : 0) | envelope << 1 | k_byte_order));
    out.i32(srs_id);
    if (enveloped) {
        out.f64(box.min_x);
        out.f64(box.max_x);
        out.f64(box.min_y);
        out.f64(box.max_y);
        if (dims == 3) {
            out.f64(box.min_z);
            out.f64(box.max_z);
        }
    }
}

/// Whether GDAL writes `g` without registering a GeoPackage geometry extension: the types of
/// the core specification (point to multipolygon, collections of them).
bool core_type(const OGRGeometry& g)
{
    const OGRwkbGeometryType type = wkbFlatten(g.getGeometryType());
    if (type == wkbGeometryCollection) {
        for (const OGRGeometry* part : *g.toGeometryCollection()) {
            if (!core_type(*part)) {
                return false;
            }
        }
        return true;
    }
    return type >= wkbPoint && type <= wkbMultiPolygon;
}

bool text_field(OGRFieldType t) { return t == OFTString; }
bool bindable_field(OGRFieldType t) { return t == OFTInteger || t == OFTInteger64 || t == OFTReal || t == OFTString; }

std::string option_value(const std::vector<std::string>& options, const std::string& key)
{
    for (const std::string& o : options) {
        if (o.size() > key.size() && o[key.size()] == '=' && EQUALN(o.c_str(), key.c_str(), key.size())) {
            return o.substr(key.size() + 1);
        }
    }
    return "";
}

} // namespace

bool sqlite_without_memory_statistics()
{
    return sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0) == SQLITE_OK;
}

void encode_gpkg(const Geometry& geometry, OGRwkbGeometryType like, std::int32_t srs_id, GpkgGeometry& out)
{
    out.blob.clear();
    out.boxed = false;
    if (geometry.empty()) {
        return;
    }
    const bool z = geometry.has_z;
    const bool multi = written_multi(geometry, like);
    const bool polygonal = !geometry.polygons.empty();
    Box3 box;
    std::size_t wkb = multi ? 9 : 0;
    if (polygonal) {
        for (const Polygon& p : geometry.polygons) {
            for (const Path& ring : p.rings) {
                box.merge_path(ring);
            }
            wkb += polygon_bytes(p, z);
        }
    } else {
        for (const Path& l : geometry.lines) {
            box.merge_path(l);
            wkb += 9 + path_bytes(l, z) - 4;
        }
    }
    const int dims = z ? 3 : 2;
    out.blob.reserve(8 + 16 * static_cast<std::size_t>(dims) + wkb);
    Bytes bytes(out.blob);
    put_header(bytes, srs_id, false, false, dims, box);
    const std::uint32_t zz = z ? k_iso_z : 0;
    if (polygonal) {
        if (multi) {
            bytes.header(wkbMultiPolygon + zz);
            bytes.u32(static_cast<std::uint32_t>(geometry.polygons.size()));
        }
        for (const Polygon& p : geometry.polygons) {
            bytes.polygon(p, z);
        }
    } else {
        if (multi) {
            bytes.header(wkbMultiLineString + zz);
            bytes.u32(static_cast<std::uint32_t>(geometry.lines.size()));
        }
        for (const Path& l : geometry.lines) {
            bytes.line(l, z);
        }
    }
    out.box.MinX = box.min_x;
    out.box.MaxX = box.max_x;
    out.box.MinY = box.min_y;
    out.box.MaxY = box.max_y;
    out.boxed = true;
}

bool encode_gpkg(const OGRGeometry* geometry, std::int32_t srs_id, GpkgGeometry& out)
{
    if (geometry == nullptr) {
        out.blob.clear();
        out.boxed = false;
        return true;
    }
    if (!core_type(*geometry)) {
        return false;
    }
    const bool point = wkbFlatten(geometry->getGeometryType()) == wkbPoint;
    const bool empty = geometry->IsEmpty();
    const int dims = geometry->getCoordinateDimension(); // 2 for XYM too: GDAL writes no M extent
    Box3 box;
    if (!point && !empty && dims == 3) {
        OGREnvelope3D e;
        geometry->getEnvelope(&e);
        box = {e.MinX, e.MaxX, e.MinY, e.MaxY, e.MinZ, e.MaxZ};
    } else if (!point && !empty) {
        OGREnvelope e;
        geometry->getEnvelope(&e);
        box.min_x = e.MinX;
        box.max_x = e.MaxX;
        box.min_y = e.MinY;
        box.max_y = e.MaxY;
    }
    out.blob.clear();
    const std::size_t header = 8 + (!point && !empty ? 16 * static_cast<std::size_t>(dims) : 0);
    out.blob.reserve(header + geometry->WkbSize());
    Bytes bytes(out.blob);
    put_header(bytes, srs_id, point, empty, dims, box);
    out.blob.resize(header + geometry->WkbSize());
    if (geometry->exportToWkb(k_byte_order ? wkbNDR : wkbXDR, reinterpret_cast<unsigned char*>(out.blob.data()) + header,
                              wkbVariantIso) != OGRERR_NONE) {
        return false;
    }
    out.boxed = !empty;
    if (out.boxed) {
        geometry->getEnvelope(&out.box);
    }
    return true;
}

std::unique_ptr<GpkgRows> GpkgRows::open(GDALDataset& dataset, OGRLayer& layer, const OGRFeatureDefn& input,
                                         const std::vector<int>& source_of, bool keeps_fids,
                                         const std::vector<std::string>& layer_options, const std::string& path,
                                         GpkgIndexBuilder* index)
{
    const OGRwkbGeometryType type = wkbFlatten(layer.GetGeomType());
    const OGRFeatureDefn& defn = *layer.GetLayerDefn();
    if (std::string(dataset.GetDriverName()) != "GPKG" || defn.GetGeomFieldCount() != 1 || type < wkbPoint ||
        type > wkbGeometryCollection || static_cast<int>(source_of.size()) != defn.GetFieldCount() ||
        CPLTestBool(option_value(layer_options, "TRUNCATE_FIELDS").empty() ? "NO"
                                                                           : option_value(layer_options, "TRUNCATE_FIELDS").c_str())) {
        return nullptr;
    }
    const char* fid_column = layer.GetFIDColumn();
    for (int i = 0; i < defn.GetFieldCount(); ++i) {
        const OGRFieldDefn& field = *defn.GetFieldDefn(i);
        if (!bindable_field(field.GetType()) || field.GetDefault() != nullptr || EQUAL(field.GetNameRef(), fid_column)) {
            return nullptr;
        }
        const int from = source_of[static_cast<std::size_t>(i)];
        if (from >= 0 && (from >= input.GetFieldCount() || input.GetFieldDefn(from)->GetType() != field.GetType())) {
            return nullptr;
        }
        if (from < 0 && field.GetType() != OFTInteger64) {
            return nullptr;
        }
    }
    auto* const db = static_cast<sqlite3*>(dataset.GetInternalHandle("SQLITE_HANDLE"));
    if (db == nullptr) {
        return nullptr;
    }
    layer.ResetReading(); // GDAL creates the table (deferred until now), without its count triggers
    return std::unique_ptr<GpkgRows>(new GpkgRows(layer, db, source_of, keeps_fids, path, index));
}

GpkgRows::GpkgRows(OGRLayer& layer, sqlite3* db, std::vector<int> source_of, bool keeps_fids,
                   const std::string& path, GpkgIndexBuilder* index)
    : m_layer(layer), m_db(db), m_index(index), m_source_of(std::move(source_of)), m_keeps_fids(keeps_fids), m_path(path)
{
    const OGRFeatureDefn& defn = *layer.GetLayerDefn();
    {
        sqlite3_stmt* query = nullptr;
        const char* text = "SELECT srs_id FROM gpkg_geometry_columns WHERE lower(table_name) = lower(?)";
        if (sqlite3_prepare_v2(m_db, text, -1, &query, nullptr) != SQLITE_OK) {
            fail(sqlite3_errmsg(m_db));
        }
        sqlite3_bind_text(query, 1, layer.GetName(), -1, SQLITE_TRANSIENT);
        const int rc = sqlite3_step(query);
        const bool found = rc == SQLITE_ROW;
        if (found) {
            m_srs_id = sqlite3_column_int(query, 0);
        }
        sqlite3_finalize(query);
        if (!found) {
            fail("the layer is not in gpkg_geometry_columns");
        }
    }
    for (int i = 0; i < defn.GetFieldCount(); ++i) {
        m_text.push_back(text_field(defn.GetFieldDefn(i)->GetType()));
        m_real.push_back(defn.GetFieldDefn(i)->GetType() == OFTReal);
    }
    m_insert = prepare(1);
    m_batch = prepare(k_batch);
}

// GDAL's statement (FeatureGenerateInsertSQL: the FID when given, the geometry, every field),
// with `rows` lists of values.
sqlite3_stmt* GpkgRows::prepare(std::size_t rows) const
{
    const OGRFeatureDefn& defn = *m_layer.GetLayerDefn();
    const auto quoted = [](const char* name) {
        char* q = sqlite3_mprintf("\"%w\"", name);
        std::string s(q);
        sqlite3_free(q);
        return s;
    };
    std::string columns;
    std::string values;
    const auto add = [&](const std::string& name) {
        columns += (columns.empty() ? "" : ", ") + name;
        values += values.empty() ? "?" : ", ?";
    };
    if (m_keeps_fids) {
        add(quoted(m_layer.GetFIDColumn()));
    }
    add(quoted(m_layer.GetGeometryColumn()));
    for (int i = 0; i < defn.GetFieldCount(); ++i) {
        add(quoted(defn.GetFieldDefn(i)->GetNameRef()));
    }
    std::string sql = "INSERT INTO " + quoted(m_layer.GetName()) + " ( " + columns + ") VALUES ";
    for (std::size_t r = 0; r < rows; ++r) {
        sql += (r == 0 ? "(" : ", (") + values + ")";
    }
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(m_db, sql.c_str(), static_cast<int>(sql.size()), &statement, nullptr) != SQLITE_OK) {
        sqlite3_finalize(statement);
        fail(sqlite3_errmsg(m_db));
    }
    return statement;
}

GpkgRows::~GpkgRows()
{
    sqlite3_finalize(m_insert);
    sqlite3_finalize(m_batch);
}

void GpkgRows::fail(const std::string& what) const
{
    throw io_error(m_path, m_layer.GetName(), "cannot write: " + what);
}

void GpkgRows::take(const OGRFeature& source, std::int64_t fid, GpkgValues& out) const
{
    out.values.resize(m_source_of.size());
    out.texts.clear();
    out.fid = fid;
    for (std::size_t i = 0; i < m_source_of.size(); ++i) {
        GpkgValues::Value& v = out.values[i];
        const int from = m_source_of[i];
        if (from < 0) { // orig_fid
            v.kind = GpkgValues::Kind::integer;
            v.integer = fid;
        } else if (!source.IsFieldSetAndNotNull(from)) {
            v.kind = GpkgValues::Kind::null;
        } else if (m_text[i]) {
            const char* text = source.GetFieldAsString(from);
            v.kind = GpkgValues::Kind::text;
            v.at = static_cast<std::uint32_t>(out.texts.size());
            v.size = static_cast<std::uint32_t>(std::strlen(text));
            out.texts.append(text, v.size);
        } else if (m_real[i]) {
            v.kind = GpkgValues::Kind::real;
            v.real = source.GetFieldAsDouble(from);
        } else {
            v.kind = GpkgValues::Kind::integer;
            v.integer = source.GetFieldAsInteger64(from);
        }
    }
}

void GpkgRows::insert(const GpkgValues& values, const GpkgGeometry& geometry)
{
    if (values.values.size() != m_source_of.size()) {
        fail("a row with " + std::to_string(values.values.size()) + " values for " + std::to_string(m_source_of.size()) + " fields");
    }
    Queued& row = m_queue.emplace_back();
    row.fid = values.fid;
    row.blob_at = m_bytes.size();
    row.blob_size = geometry.blob.size();
    m_bytes += geometry.blob;
    row.values_at = m_values.size();
    for (GpkgValues::Value v : values.values) {
        if (v.kind == GpkgValues::Kind::text) {
            const std::size_t at = m_bytes.size();
            m_bytes.append(values.texts, v.at, v.size);
            v.at = static_cast<std::uint32_t>(at);
        }
        m_values.push_back(v);
    }
    row.box = geometry.box;
    row.boxed = geometry.boxed;
    if (m_queue.size() == k_batch || m_bytes.size() > k_batch_bytes) {
        flush(); // a heavy row goes in with the few before it, one by one: the queue stays small
    }
}

void GpkgRows::flush()
{
    if (m_queue.empty()) {
        return;
    }
    // The connection's mutex held once: each call below would take and give it back (SQLite's
    // serialized mode); nested, it is a count.
    sqlite3_mutex* const mutex = sqlite3_db_mutex(m_db);
    sqlite3_mutex_enter(mutex);
    struct Leave {
        sqlite3_mutex* m;
        ~Leave() { sqlite3_mutex_leave(m); }
    } leave{mutex};
    struct Clear { // queued rows are gone after this, inserted or not
        GpkgRows& r;
        ~Clear()
        {
            r.m_queue.clear();
            r.m_bytes.clear();
            r.m_values.clear();
        }
    } clear{*this};
    if (m_queue.size() == k_batch && m_bytes.size() <= k_batch_bytes) {
        run_batch();
        return;
    }
    for (const Queued& row : m_queue) {
        run_one(row);
    }
}

// Binds `row` from parameter `at` on; returns the first failing bind's code (else SQLITE_OK).
// Blobs and texts are bound SQLITE_STATIC: m_bytes does not change until the statement ran.
int GpkgRows::bind(sqlite3_stmt* statement, int at, const Queued& row) const
{
    int rc = SQLITE_OK;
    const auto bound = [&](int result) {
        if (rc == SQLITE_OK) {
            rc = result;
        }
    };
    if (m_keeps_fids) {
        bound(sqlite3_bind_int64(statement, at++, row.fid));
    }
    if (row.blob_size == 0) {
        bound(sqlite3_bind_null(statement, at++));
    } else {
        bound(sqlite3_bind_blob(statement, at++, m_bytes.data() + row.blob_at, static_cast<int>(row.blob_size), SQLITE_STATIC));
    }
    for (std::size_t i = 0; i < m_source_of.size(); ++i, ++at) {
        const GpkgValues::Value& v = m_values[row.values_at + i];
        switch (v.kind) {
        case GpkgValues::Kind::null: bound(sqlite3_bind_null(statement, at)); break;
        case GpkgValues::Kind::integer: bound(sqlite3_bind_int64(statement, at, v.integer)); break;
        case GpkgValues::Kind::real: bound(sqlite3_bind_double(statement, at, v.real)); break;
        case GpkgValues::Kind::text:
            bound(sqlite3_bind_text(statement, at, m_bytes.data() + v.at, static_cast<int>(v.size), SQLITE_STATIC));
            break;
        }
    }
    return rc;
}

namespace {

/// Runs a statement with its values bound; SQLITE_DONE on success. Leaves it ready again.
int step(sqlite3_stmt* statement, int bound)
{
    const int rc = bound == SQLITE_OK ? sqlite3_step(statement) : bound;
    sqlite3_reset(statement);
    sqlite3_clear_bindings(statement);
    return rc;
}

/// A row SQLite refuses for its values (GDAL reports those per feature and goes on), not for
/// the file.
bool refusal(int rc)
{
    const int primary = rc & 0xff;
    return primary == SQLITE_CONSTRAINT || primary == SQLITE_MISMATCH || primary == SQLITE_TOOBIG;
}

} // namespace

void GpkgRows::run_batch()
{
    const int per_row = static_cast<int>(m_source_of.size()) + (m_keeps_fids ? 2 : 1);
    int bound = SQLITE_OK;
    for (std::size_t r = 0; r < m_queue.size() && bound == SQLITE_OK; ++r) {
        bound = bind(m_batch, 1 + static_cast<int>(r) * per_row, m_queue[r]);
    }
    const int rc = step(m_batch, bound);
    if (rc == SQLITE_DONE) {
        // Without FIDs given, AUTOINCREMENT numbers the statement's rows one after the other.
        const std::int64_t last = sqlite3_last_insert_rowid(m_db);
        for (std::size_t r = 0; r < m_queue.size(); ++r) {
            inserted(m_queue[r], m_keeps_fids ? m_queue[r].fid
                                             : last - static_cast<std::int64_t>(m_queue.size() - 1 - r));
        }
        return;
    }
    if (!refusal(rc)) {
        fail(sqlite3_errmsg(m_db));
    }
    for (const Queued& row : m_queue) { // SQLite undid the statement: each row alone
        run_one(row);
    }
}

void GpkgRows::run_one(const Queued& row)
{
    const int rc = step(m_insert, bind(m_insert, 1, row));
    if (rc == SQLITE_DONE) {
        inserted(row, sqlite3_last_insert_rowid(m_db));
        return;
    }
    if (!refusal(rc)) {
        fail(sqlite3_errmsg(m_db));
    }
    m_refusals.push_back({row.fid, std::string("failed to execute insert : ") + sqlite3_errmsg(m_db)}); // GDAL's words
}

void GpkgRows::inserted(const Queued& row, std::int64_t rowid)
{
    ++m_inserted;
    if (row.boxed) {
        include(row.box);
        if (m_index != nullptr) {
            m_index->add(rowid, row.box);
        }
    }
}

void GpkgRows::include(const OGRGeometry* geometry)
{
    if (geometry != nullptr && !geometry->IsEmpty()) {
        OGREnvelope box;
        geometry->getEnvelope(&box);
        include(box);
    }
}

// GDAL's UpdateExtent: the first box, then OGREnvelope::Merge.
void GpkgRows::include(const OGREnvelope& box)
{
    if (!m_has_extent) {
        m_extent = box;
        m_has_extent = true;
    }
    m_extent.Merge(box);
}

void GpkgRows::run(const std::string& sql) const
{
    char* error = nullptr;
    if (sqlite3_exec(m_db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
        const std::string message = error ? error : sqlite3_errmsg(m_db);
        sqlite3_free(error);
        fail(message);
    }
}

void GpkgRows::finish(std::size_t features)
{
    {
        ScopedErrorCapture capture;
        if (m_layer.SyncToDisk() != OGRERR_NONE || !capture.errors().empty()) {
            fail(capture.last_error("GDAL could not save the layer's metadata"));
        }
    }
    const auto statement = [](char* text) {
        std::string s(text);
        sqlite3_free(text);
        return s;
    };
    if (m_has_extent) {
        // GDAL's SaveExtent text, so SQLite reads the same numbers back.
        run(statement(sqlite3_mprintf("UPDATE gpkg_contents SET min_x = %.18g, min_y = %.18g, max_x = %.18g, max_y = %.18g "
                                      "WHERE lower(table_name) = lower('%q') AND Lower(data_type) = 'features'",
                                      m_extent.MinX, m_extent.MinY, m_extent.MaxX, m_extent.MaxY, m_layer.GetName())));
    }
    sqlite3_stmt* query = nullptr;
    bool counted = false;
    if (sqlite3_prepare_v2(m_db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'gpkg_ogr_contents'", -1,
                           &query, nullptr) == SQLITE_OK) {
        counted = sqlite3_step(query) == SQLITE_ROW;
    }
    sqlite3_finalize(query);
    if (counted) { // absent with -dsco ADD_GPKG_OGR_CONTENTS=NO
        run(statement(sqlite3_mprintf("UPDATE gpkg_ogr_contents SET feature_count = %lld WHERE lower(table_name) = lower('%q')",
                                      static_cast<long long>(features), m_layer.GetName())));
    }
}

} // namespace trisnap
