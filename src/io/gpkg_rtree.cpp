#include "io/gpkg_rtree.hpp"

#include "io/external_sort.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/sql_quote.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <functional>
#include <cstring>
#include <limits>
#include <utility>

namespace trisnap {
namespace {

constexpr std::size_t k_cell_bytes = 8 + 4 * 4; // id, then minx, maxx, miny, maxy
constexpr std::size_t k_max_cells = 51;         // SQLite's RTREE_MAXCELLS

float down(double d)
{
    if (!(d <= static_cast<double>(FLT_MAX))) {
        return FLT_MAX; // beyond a float: the largest finite one is still <= d (no NaN comes here)
    }
    if (d < -static_cast<double>(FLT_MAX)) {
        return -std::numeric_limits<float>::infinity();
    }
    float f = static_cast<float>(d);
    if (static_cast<double>(f) > d) {
        f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    }
    return f;
}

float up(double d)
{
    if (!(d >= -static_cast<double>(FLT_MAX))) {
        return -FLT_MAX;
    }
    if (d > static_cast<double>(FLT_MAX)) {
        return std::numeric_limits<float>::infinity();
    }
    float f = static_cast<float>(d);
    if (static_cast<double>(f) < d) {
        f = std::nextafter(f, std::numeric_limits<float>::infinity());
    }
    return f;
}

// Twice the centre. A box from -infinity to +infinity (coordinates beyond a float's range on
// both sides) has no centre: 0 stands in, as NaN would break the sorts' ordering.
double centre(float lo, float hi)
{
    const double c = static_cast<double>(lo) + static_cast<double>(hi);
    return std::isnan(c) ? 0.0 : c;
}
double centre_x(const RtreeEntry& e) { return centre(e.min_x, e.max_x); }
double centre_y(const RtreeEntry& e) { return centre(e.min_y, e.max_y); }

/// `items[first, last)` sorted by (centre `a`, centre `b`, id): a total order (ids are unique),
/// so one result whatever the sort. The centres are worked out once, not in every comparison
/// (Andorra x43's 247,551 boxes: the index's packing took 85 ms of the write phase's 0.8 s).
template <class A, class B>
void sort_by_centres(std::vector<RtreeEntry>& items, std::size_t first, std::size_t last, A a, B b)
{
    struct Key {
        double a, b;
        RtreeEntry e;
    };
    std::vector<Key> keys;
    keys.reserve(last - first);
    for (std::size_t i = first; i < last; ++i) {
        keys.push_back(Key{a(items[i]), b(items[i]), items[i]});
    }
    std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
        if (x.a != y.a) {
            return x.a < y.a;
        }
        if (x.b != y.b) {
            return x.b < y.b;
        }
        return x.e.id < y.e.id;
    });
    for (std::size_t i = first; i < last; ++i) {
        items[i] = keys[i - first].e;
    }
}

/// The order of sort_by_centres(items, .., centre_x, centre_y): the level's first sort, for the
/// runs on disk.
struct ByCentreX {
    bool operator()(const RtreeEntry& p, const RtreeEntry& q) const
    {
        const double px = centre_x(p), qx = centre_x(q);
        if (px != qx) {
            return px < qx;
        }
        const double py = centre_y(p), qy = centre_y(q);
        if (py != qy) {
            return py < qy;
        }
        return p.id < q.id;
    }
};

/// A row of the parent or rowid table: (node or FID, node number); keys are unique.
struct KeyValue {
    std::int64_t key = 0;
    std::int64_t value = 0;
};
struct ByKey {
    bool operator()(const KeyValue& p, const KeyValue& q) const { return p.key < q.key; }
};

/// The nodes of one level in order, on disk: each as its cell count (u16) and its cells.
class NodeFile {
public:
    using Fail = std::function<void(const std::string&)>;
    NodeFile(std::filesystem::path path, Fail fail) : m_path(std::move(path)), m_fail(std::move(fail))
    {
        m_file = std::fopen(m_path.c_str(), "w+b");
        if (m_file == nullptr) {
            m_fail("cannot create " + m_path.string() + ": " + std::strerror(errno));
        }
    }
    ~NodeFile()
    {
        if (m_file != nullptr) {
            std::fclose(m_file);
        }
        std::error_code ec;
        std::filesystem::remove(m_path, ec);
    }
    NodeFile(const NodeFile&) = delete;
    NodeFile& operator=(const NodeFile&) = delete;

    void write(const std::vector<RtreeEntry>& cells)
    {
        const auto count = static_cast<std::uint16_t>(cells.size());
        if (std::fwrite(&count, sizeof count, 1, m_file) != 1 ||
            std::fwrite(cells.data(), sizeof(RtreeEntry), cells.size(), m_file) != cells.size()) {
            m_fail("cannot write " + m_path.string() + ": " + std::strerror(errno));
        }
    }
    /// After the last write(): read from the start.
    void rewind()
    {
        if (std::fflush(m_file) != 0 || std::fseek(m_file, 0, SEEK_SET) != 0) {
            m_fail("cannot write " + m_path.string() + ": " + std::strerror(errno));
        }
    }
    void read(std::vector<RtreeEntry>& cells)
    {
        std::uint16_t count = 0;
        if (std::fread(&count, sizeof count, 1, m_file) != 1) {
            m_fail("cannot read " + m_path.string() + (std::ferror(m_file) ? std::string(": ") + std::strerror(errno) : ": cut short"));
        }
        cells.resize(count);
        if (std::fread(cells.data(), sizeof(RtreeEntry), count, m_file) != count) {
            m_fail("cannot read " + m_path.string() + ": cut short");
        }
    }

private:
    std::filesystem::path m_path;
    Fail m_fail;
    std::FILE* m_file = nullptr;
};

/// One level of Sort-Tile-Recursive on items that come from `next` sorted by (centre x, centre y,
/// id): ceil(sqrt(P)) slices of P = ceil(n / max_cells) nodes' worth, each sorted by (centre y,
/// centre x, id) and cut into nodes of at most max_cells (the last of a slice may hold fewer),
/// each given to `emit(cells, its index in the level)`. Holds one slice at a time; returns the
/// nodes made (no items: one empty node).
template <class Next, class Emit>
std::uint64_t pack_level_streamed(std::uint64_t n, std::size_t max_cells, Next&& next, Emit&& emit)
{
    if (n == 0) {
        std::vector<RtreeEntry> none;
        emit(none, std::uint64_t{0});
        return 1;
    }
    const std::uint64_t leaves = (n + max_cells - 1) / max_cells;
    auto slices = static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(leaves))));
    while (slices * slices < leaves) {
        ++slices;
    }
    const std::uint64_t per_slice = slices * max_cells;
    std::vector<RtreeEntry> slice;
    slice.reserve(static_cast<std::size_t>(std::min(per_slice, n)));
    std::vector<RtreeEntry> cells;
    std::uint64_t k = 0;
    RtreeEntry e;
    for (;;) {
        slice.clear();
        while (slice.size() < per_slice && next(e)) {
            slice.push_back(e);
        }
        if (slice.empty()) {
            return k;
        }
        sort_by_centres(slice, 0, slice.size(), centre_y, centre_x);
        for (std::size_t at = 0; at < slice.size(); at += max_cells) {
            const auto it = slice.begin() + static_cast<std::ptrdiff_t>(at);
            cells.assign(it, it + static_cast<std::ptrdiff_t>(std::min(max_cells, slice.size() - at)));
            emit(cells, k++);
        }
    }
}

/// One level in memory: the items sorted, then packed as above.
std::vector<std::vector<RtreeEntry>> pack_level(std::vector<RtreeEntry> items, std::size_t max_cells)
{
    sort_by_centres(items, 0, items.size(), centre_x, centre_y);
    std::vector<std::vector<RtreeEntry>> nodes;
    nodes.reserve((items.size() + max_cells - 1) / max_cells + 1);
    std::size_t at = 0;
    pack_level_streamed(items.size(), max_cells,
                        [&](RtreeEntry& e) {
                            if (at == items.size()) {
                                return false;
                            }
                            e = items[at++];
                            return true;
                        },
                        [&](std::vector<RtreeEntry>& cells, std::uint64_t) { nodes.push_back(cells); });
    return nodes;
}

RtreeEntry bounds(const std::vector<RtreeEntry>& cells, std::int64_t id)
{
    RtreeEntry b = cells.front();
    for (const RtreeEntry& c : cells) {
        b.min_x = std::min(b.min_x, c.min_x);
        b.max_x = std::max(b.max_x, c.max_x);
        b.min_y = std::min(b.min_y, c.min_y);
        b.max_y = std::max(b.max_y, c.max_y);
    }
    b.id = id;
    return b;
}

void put_u16(std::string& out, std::size_t at, unsigned v)
{
    out[at] = static_cast<char>((v >> 8) & 0xff);
    out[at + 1] = static_cast<char>(v & 0xff);
}

void put_u64(std::string& out, std::size_t at, std::uint64_t v)
{
    for (int i = 0; i < 8; ++i) {
        out[at + static_cast<std::size_t>(i)] = static_cast<char>((v >> (56 - 8 * i)) & 0xff);
    }
}

void put_float(std::string& out, std::size_t at, float f)
{
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    for (int i = 0; i < 4; ++i) {
        out[at + static_cast<std::size_t>(i)] = static_cast<char>((bits >> (24 - 8 * i)) & 0xff);
    }
}


/// Where the index goes, for the error that names it: OUT's path, the layer, and what was left at
/// OUT (the writer's outcome).
struct IndexTarget {
    const std::string& path;
    const std::string& layer;
    const std::string& outcome;
    [[noreturn]] void fail(const std::string& message) const
    {
        throw io_error(path, layer, "cannot write the spatial index: " + message + outcome);
    }
};

/// A statement prepared once on SQLite's own connection and run again with new values bound:
/// no SQL text per row for SQLite to compile, nor for GDAL's ExecuteSQL to scan (it searches
/// each statement's text for its own keywords, case-insensitively: 60 ms of the index's 0.3 s
/// on 247,551 features when the rows went in as text).
class Prepared {
public:
    Prepared(sqlite3* db, const std::string& text, const IndexTarget& target) : m_db(db), m_target(target)
    {
        check(sqlite3_prepare_v2(m_db, text.c_str(), static_cast<int>(text.size()), &m_statement, nullptr));
    }
    ~Prepared() { sqlite3_finalize(m_statement); }
    Prepared(const Prepared&) = delete;
    Prepared& operator=(const Prepared&) = delete;

    void bind(int at, std::int64_t value) { check(sqlite3_bind_int64(m_statement, at, value)); }
    void bind(int at, const std::string& blob)
    {
        check(sqlite3_bind_blob(m_statement, at, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT));
    }
    /// Runs it with the values bound, then makes it ready for the next ones.
    void run()
    {
        const int rc = sqlite3_step(m_statement);
        sqlite3_reset(m_statement);
        check(rc == SQLITE_DONE ? SQLITE_OK : rc);
    }

private:
    void check(int rc) const
    {
        if (rc != SQLITE_OK) {
            m_target.fail(sqlite3_errmsg(m_db));
        }
    }

    sqlite3* m_db;
    const IndexTarget& m_target;
    sqlite3_stmt* m_statement = nullptr;
};

/// The rows 0 .. count - 1 of two columns into `table` through SQLite's connection `db`, in that
/// order: `bind(statement, first parameter, i)` binds row i's two values. Rows go `k_rows` to a
/// statement (one VALUES list of bound parameters, compiled once), the rest one at a time.
template <class Bind>
void insert_rows(sqlite3* db, const IndexTarget& target, const std::string& table, std::size_t count, const Bind& bind)
{
    constexpr std::size_t k_rows = 128; // 256 parameters: within SQLite's limit of 999 since 3.0
    const auto text = [&](std::size_t rows) {
        std::string t = "INSERT INTO " + sql_identifier(table) + " VALUES ";
        for (std::size_t r = 0; r < rows; ++r) {
            t += r == 0 ? "(?,?)" : ",(?,?)";
        }
        return t;
    };
    std::size_t i = 0;
    if (count >= k_rows) {
        Prepared many(db, text(k_rows), target);
        for (; i + k_rows <= count; i += k_rows) {
            for (std::size_t r = 0; r < k_rows; ++r) {
                bind(many, static_cast<int>(2 * r) + 1, i + r);
            }
            many.run();
        }
    }
    if (i < count) {
        Prepared one(db, text(1), target);
        for (; i < count; ++i) {
            bind(one, 1, i);
            one.run();
        }
    }
}

/// pack_rtree()'s tree written: the root, the nodes 2.. in number order, their parents, the
/// rowid rows in FID order.
void write_packed_tree(sqlite3* db, const IndexTarget& target, const std::string& rtree, std::size_t node_size,
                       const PackedRtree& tree)
{
    const auto node_blob = [&](std::size_t k) { return rtree_node_blob(tree.nodes[k], tree.depth, k == 0, node_size); };
    {
        Prepared root(db, "UPDATE " + sql_identifier(rtree + "_node") + " SET data = ? WHERE nodeno = 1", target);
        root.bind(1, node_blob(0));
        root.run();
    }
    const std::size_t nodes = tree.nodes.size() - 1; // below the root: nodes[1..]
    insert_rows(db, target, rtree + "_node", nodes, [&](Prepared& p, int at, std::size_t i) {
        p.bind(at, static_cast<std::int64_t>(i + 2));
        p.bind(at + 1, node_blob(i + 1));
    });
    insert_rows(db, target, rtree + "_parent", nodes, [&](Prepared& p, int at, std::size_t i) {
        p.bind(at, static_cast<std::int64_t>(i + 2));
        p.bind(at + 1, tree.parent[i + 1]);
    });
    // The leaves' cells are the FIDs: the rowid table maps each to its leaf, in FID order.
    std::vector<std::pair<std::int64_t, std::int64_t>> leaf_of;
    for (std::size_t k = tree.first_leaf; k < tree.nodes.size(); ++k) {
        for (const RtreeEntry& cell : tree.nodes[k]) {
            leaf_of.emplace_back(cell.id, static_cast<std::int64_t>(k) + 1);
        }
    }
    std::sort(leaf_of.begin(), leaf_of.end());
    insert_rows(db, target, rtree + "_rowid", leaf_of.size(), [&](Prepared& p, int at, std::size_t i) {
        p.bind(at, leaf_of[i].first);
        p.bind(at + 1, leaf_of[i].second);
    });
}

using BoxSorter = ExternalSorter<RtreeEntry, ByCentreX>;
using RowSorter = ExternalSorter<KeyValue, ByKey>;

/// The tree of the boxes `level0` holds (finished, in ByCentreX order), written as the in-memory
/// path writes pack_rtree()'s: the root, the nodes 2.. in number order, their parents, the rowid
/// rows in FID order. Levels are packed from the leaves up; each level's nodes go to a file, the
/// next level's items (their boxes), the parent rows and the rowid rows to sorters of at most
/// `capacity` records in memory. The numbers are known before any node is made: every level
/// but the last slice of each is cut into full nodes, so a level of n items has ceil(n / C) nodes.
void write_spilled_tree(sqlite3* db, const IndexTarget& target, const std::string& rtree, std::size_t node_size,
                        std::size_t max_cells, std::unique_ptr<BoxSorter> level0, const std::filesystem::path& scratch,
                        const std::string& stem, std::size_t capacity, const NodeFile::Fail& fail)
{
    const std::uint64_t n = level0->size();
    std::vector<std::uint64_t> sizes{n == 0 ? 1 : (n + max_cells - 1) / max_cells};
    while (sizes.back() > 1) {
        sizes.push_back((sizes.back() + max_cells - 1) / max_cells);
    }
    const std::size_t top = sizes.size() - 1;
    std::vector<std::int64_t> first(sizes.size());
    first[top] = 1;
    for (std::size_t l = top; l-- > 0;) {
        first[l] = first[l + 1] + static_cast<std::int64_t>(sizes[l + 1]);
    }
    const auto name = [&](const std::string& what) { return stem + "-" + what; };
    RowSorter rowids(scratch, name("rowid"), capacity, ByKey{}, fail);
    std::vector<std::unique_ptr<RowSorter>> parents(top); // parents[l]: of the nodes of level l
    std::vector<std::unique_ptr<NodeFile>> files(top + 1);
    std::unique_ptr<BoxSorter> items = std::move(level0);
    for (std::size_t l = 0; l <= top; ++l) {
        if (l > 0) {
            parents[l - 1] = std::make_unique<RowSorter>(scratch, name("parent-" + std::to_string(l - 1)), capacity, ByKey{}, fail);
        }
        std::unique_ptr<BoxSorter> above =
            l < top ? std::make_unique<BoxSorter>(scratch, name("level-" + std::to_string(l + 1)), capacity, ByCentreX{}, fail) : nullptr;
        files[l] = std::make_unique<NodeFile>(scratch / (name("nodes-" + std::to_string(l)) + ".bin"), fail);
        const std::uint64_t count = l == 0 ? n : sizes[l - 1];
        const std::uint64_t made = pack_level_streamed(count, max_cells, [&](RtreeEntry& e) { return items->next(e); },
                                                       [&](std::vector<RtreeEntry>& cells, std::uint64_t k) {
            const std::int64_t number = first[l] + static_cast<std::int64_t>(k);
            if (above) {
                above->add(bounds(cells, static_cast<std::int64_t>(k)));
            }
            for (RtreeEntry& c : cells) {
                if (l == 0) {
                    rowids.add(KeyValue{c.id, number});
                } else {
                    c.id += first[l - 1];
                    parents[l - 1]->add(KeyValue{c.id, number});
                }
            }
            files[l]->write(cells);
        });
        if (made != sizes[l]) {
            fail("level " + std::to_string(l) + " of the tree has " + std::to_string(made) + " nodes, not " + std::to_string(sizes[l]));
        }
        items = std::move(above);
        if (items) {
            items->finish();
        }
    }
    std::vector<RtreeEntry> cells;
    files[top]->rewind();
    files[top]->read(cells);
    {
        Prepared root(db, "UPDATE " + sql_identifier(rtree + "_node") + " SET data = ? WHERE nodeno = 1", target);
        root.bind(1, rtree_node_blob(cells, static_cast<int>(top), true, node_size));
        root.run();
    }
    // Nodes 2.. are the levels below the root from the top down, each in its order.
    const auto below_root = static_cast<std::size_t>(first[0] - 1 + static_cast<std::int64_t>(sizes[0]) - 1);
    std::size_t level = top;
    std::uint64_t left = 0; // nodes of `level` still to read
    insert_rows(db, target, rtree + "_node", below_root, [&](Prepared& p, int at, std::size_t i) {
        while (left == 0) {
            --level;
            left = sizes[level];
            files[level]->rewind();
        }
        files[level]->read(cells);
        --left;
        p.bind(at, static_cast<std::int64_t>(i + 2));
        p.bind(at + 1, rtree_node_blob(cells, static_cast<int>(top), false, node_size));
    });
    files.clear();
    for (std::unique_ptr<RowSorter>& s : parents) {
        s->finish();
    }
    level = top;
    insert_rows(db, target, rtree + "_parent", below_root, [&](Prepared& p, int at, std::size_t i) {
        KeyValue row;
        while (!parents[level - 1]->next(row)) {
            parents[--level].reset();
        }
        if (row.key != static_cast<std::int64_t>(i + 2)) {
            fail("node " + std::to_string(row.key) + " came where node " + std::to_string(i + 2) + " was due");
        }
        p.bind(at, row.key);
        p.bind(at + 1, row.value);
    });
    parents.clear();
    rowids.finish();
    insert_rows(db, target, rtree + "_rowid", static_cast<std::size_t>(n), [&](Prepared& p, int at, std::size_t) {
        KeyValue row;
        if (!rowids.next(row)) {
            fail("the rowid rows ended early");
        }
        p.bind(at, row.key);
        p.bind(at + 1, row.value);
    });
}

/// SQL on the GeoPackage through GDAL (its SQLite connection, inside the writer's transaction):
/// the statements that make the index's tables, its triggers and its extension row.
class Sql {
public:
    Sql(GDALDataset& dataset, const IndexTarget& target) : m_dataset(dataset), m_target(target) {}

    void run(const std::string& statement)
    {
        ScopedErrorCapture capture;
        OGRLayer* result = m_dataset.ExecuteSQL(statement.c_str(), nullptr, nullptr);
        if (result != nullptr) {
            m_dataset.ReleaseResultSet(result);
        }
        check(capture);
    }

    std::int64_t integer(const std::string& query)
    {
        ScopedErrorCapture capture;
        OGRLayer* result = m_dataset.ExecuteSQL(query.c_str(), nullptr, nullptr);
        std::int64_t value = -1;
        if (result != nullptr) {
            OGRFeatureUniquePtr row(result->GetNextFeature());
            if (row && row->IsFieldSetAndNotNull(0)) {
                value = row->GetFieldAsInteger64(0);
            }
            m_dataset.ReleaseResultSet(result);
        }
        check(capture);
        return value;
    }

private:
    void check(const ScopedErrorCapture& capture) const
    {
        if (!capture.errors().empty()) {
            m_target.fail(capture.last_error());
        }
    }

    GDALDataset& m_dataset;
    const IndexTarget& m_target;
};

/// The GeoPackage R-tree extension's triggers (spec 1.2, F.3), which keep the index in step
/// with later edits of the table.
std::vector<std::string> rtree_triggers(const std::string& table, const std::string& column, const std::string& fid,
                                        const std::string& rtree)
{
    const std::string t = sql_identifier(table);
    const std::string c = sql_identifier(column);
    const std::string i = sql_identifier(fid);
    const std::string r = sql_identifier(rtree);
    const std::string row = "VALUES (NEW." + i + ",ST_MinX(NEW." + c + "), ST_MaxX(NEW." + c + "),ST_MinY(NEW." + c +
                            "), ST_MaxY(NEW." + c + "))";
    const std::string has = "(NEW." + c + " NOTNULL AND NOT ST_IsEmpty(NEW." + c + "))";
    const std::string lacks = "(NEW." + c + " ISNULL OR ST_IsEmpty(NEW." + c + "))";
    const auto name = [&](const char* suffix) { return sql_identifier(rtree + "_" + suffix); };
    return {
        "CREATE TRIGGER " + name("insert") + " AFTER INSERT ON " + t + " WHEN (new." + c + " NOT NULL AND NOT ST_IsEmpty(NEW." +
            c + ")) BEGIN INSERT OR REPLACE INTO " + r + " " + row + "; END",
        "CREATE TRIGGER " + name("update1") + " AFTER UPDATE OF " + c + " ON " + t + " WHEN OLD." + i + " = NEW." + i +
            " AND " + has + " BEGIN INSERT OR REPLACE INTO " + r + " " + row + "; END",
        "CREATE TRIGGER " + name("update2") + " AFTER UPDATE OF " + c + " ON " + t + " WHEN OLD." + i + " = NEW." + i +
            " AND " + lacks + " BEGIN DELETE FROM " + r + " WHERE id = OLD." + i + "; END",
        "CREATE TRIGGER " + name("update3") + " AFTER UPDATE ON " + t + " WHEN OLD." + i + " != NEW." + i + " AND " + has +
            " BEGIN DELETE FROM " + r + " WHERE id = OLD." + i + "; INSERT OR REPLACE INTO " + r + " " + row + "; END",
        "CREATE TRIGGER " + name("update4") + " AFTER UPDATE ON " + t + " WHEN OLD." + i + " != NEW." + i + " AND " + lacks +
            " BEGIN DELETE FROM " + r + " WHERE id IN (OLD." + i + ", NEW." + i + "); END",
        "CREATE TRIGGER " + name("delete") + " AFTER DELETE ON " + t + " WHEN old." + c + " NOT NULL BEGIN DELETE FROM " + r +
            " WHERE id = OLD." + i + "; END",
    };
}

} // namespace

RtreeEntry rtree_entry(std::int64_t id, const OGREnvelope& box)
{
    RtreeEntry e;
    e.id = id;
    e.min_x = down(box.MinX);
    e.max_x = up(box.MaxX);
    e.min_y = down(box.MinY);
    e.max_y = up(box.MaxY);
    return e;
}

PackedRtree pack_rtree(std::vector<RtreeEntry> entries, std::size_t max_cells)
{
    max_cells = std::max<std::size_t>(2, max_cells);
    // levels[0] holds the leaves; above, a cell's id is its child's index in the level below.
    std::vector<std::vector<std::vector<RtreeEntry>>> levels;
    levels.push_back(pack_level(std::move(entries), max_cells));
    while (levels.back().size() > 1) {
        const auto& below = levels.back();
        std::vector<RtreeEntry> items;
        items.reserve(below.size());
        for (std::size_t k = 0; k < below.size(); ++k) {
            items.push_back(bounds(below[k], static_cast<std::int64_t>(k)));
        }
        levels.push_back(pack_level(std::move(items), max_cells));
    }
    // Numbers from the root (1) down, level by level.
    std::vector<std::int64_t> first(levels.size());
    std::int64_t next = 1;
    for (std::size_t l = levels.size(); l-- > 0;) {
        first[l] = next;
        next += static_cast<std::int64_t>(levels[l].size());
    }
    PackedRtree tree;
    tree.depth = static_cast<int>(levels.size()) - 1;
    tree.first_leaf = static_cast<std::size_t>(first[0] - 1);
    tree.parent.assign(static_cast<std::size_t>(next - 1), 0);
    for (std::size_t l = levels.size(); l-- > 0;) {
        for (std::vector<RtreeEntry>& node : levels[l]) {
            const auto number = static_cast<std::int64_t>(tree.nodes.size()) + 1;
            if (l > 0) {
                for (RtreeEntry& cell : node) {
                    cell.id += first[l - 1];
                    tree.parent[static_cast<std::size_t>(cell.id - 1)] = number;
                }
            }
            tree.nodes.push_back(std::move(node));
        }
    }
    return tree;
}

std::string rtree_node_blob(const std::vector<RtreeEntry>& cells, int depth, bool root, std::size_t node_size)
{
    std::string blob(node_size, '\0');
    put_u16(blob, 0, root ? static_cast<unsigned>(depth) : 0U);
    put_u16(blob, 2, static_cast<unsigned>(cells.size()));
    std::size_t at = 4;
    for (const RtreeEntry& c : cells) {
        put_u64(blob, at, static_cast<std::uint64_t>(c.id));
        put_float(blob, at + 8, c.min_x);
        put_float(blob, at + 12, c.max_x);
        put_float(blob, at + 16, c.min_y);
        put_float(blob, at + 20, c.max_y);
        at += k_cell_bytes;
    }
    return blob;
}

void GpkgIndexBuilder::add(std::int64_t fid, const OGRGeometry* geometry)
{
    if (m_fallback || geometry == nullptr || geometry->IsEmpty()) {
        return;
    }
    OGREnvelope box;
    geometry->getEnvelope(&box);
    add(fid, box);
}

struct GpkgIndexBuilder::Spill {
    std::string stem;
    std::unique_ptr<BoxSorter> boxes;
};

GpkgIndexBuilder::GpkgIndexBuilder(std::size_t max_entries, std::filesystem::path scratch, std::string path)
    : m_max_entries(max_entries), m_scratch(std::move(scratch)), m_path(std::move(path))
{
}

GpkgIndexBuilder::~GpkgIndexBuilder() = default;

void GpkgIndexBuilder::add(std::int64_t fid, const OGREnvelope& box)
{
    if (m_fallback) {
        return;
    }
    if (m_spill) {
        m_spill->boxes->add(rtree_entry(fid, box));
        return;
    }
    if (m_entries.size() >= m_max_entries) {
        if (m_scratch.empty()) {
            m_fallback = true;
            std::vector<RtreeEntry>().swap(m_entries);
            return;
        }
        static std::atomic<unsigned> builders{0}; // several layers of one OUT share the directory
        m_spill = std::make_unique<Spill>();
        m_spill->stem = "rtree-" + std::to_string(builders++);
        const std::string path = m_path;
        m_spill->boxes = std::make_unique<BoxSorter>(m_scratch, m_spill->stem + "-boxes", m_max_entries, ByCentreX{},
                                                     [path](const std::string& m) {
                                                         throw io_error(path, "", "cannot write the spatial index: " + m);
                                                     });
        m_spill->boxes->take(std::move(m_entries)); // the first run, spilled by the next add
        m_entries = {};
        m_spill->boxes->add(rtree_entry(fid, box));
        return;
    }
    m_entries.push_back(rtree_entry(fid, box));
}

void GpkgIndexBuilder::write(GDALDataset& dataset, OGRLayer& layer, const std::string& path, const std::string& outcome)
{
    const std::string table = layer.GetName();
    const std::string column = layer.GetGeometryColumn();
    const IndexTarget target{path, table, outcome};
    Sql sql(dataset, target);
    // The rows go in through GDAL's own SQLite connection (its GeoPackage driver hands it out);
    // without it, or above the box budget, GDAL builds the index its own way.
    auto* const db = static_cast<sqlite3*>(dataset.GetInternalHandle("SQLITE_HANDLE"));
    if (m_fallback || db == nullptr) {
        sql.run("SELECT CreateSpatialIndex(" + sql_literal(table) + ", " + sql_literal(column) + ")");
        return;
    }
    const std::string rtree = "rtree_" + table + "_" + column;
    sql.run("CREATE VIRTUAL TABLE " + sql_identifier(rtree) + " USING rtree(id, minx, maxx, miny, maxy)");
    // SQLite sizes every node like the root it just made (page size - 64, at most 51 cells).
    const std::int64_t node_size = sql.integer("SELECT length(data) FROM " + sql_identifier(rtree + "_node") + " WHERE nodeno = 1");
    if (node_size < static_cast<std::int64_t>(4 + 2 * k_cell_bytes)) {
        target.fail("SQLite made an R-tree node of " + std::to_string(node_size) + " bytes");
    }
    const std::size_t max_cells = std::min(k_max_cells, (static_cast<std::size_t>(node_size) - 4) / k_cell_bytes);
    if (m_spill) {
        m_spill->boxes->on_failure([&](const std::string& m) { target.fail(m); });
        m_spill->boxes->finish();
        write_spilled_tree(db, target, rtree, static_cast<std::size_t>(node_size), max_cells, std::move(m_spill->boxes), m_scratch,
                           m_spill->stem, std::max<std::size_t>(m_max_entries / 4, 1), [&](const std::string& m) { target.fail(m); });
        m_spill.reset();
    } else {
        write_packed_tree(db, target, rtree, static_cast<std::size_t>(node_size), pack_rtree(std::move(m_entries), max_cells));
        m_entries = {};
    }
    for (const std::string& trigger : rtree_triggers(table, column, layer.GetFIDColumn(), rtree)) {
        sql.run(trigger);
    }
    sql.run("CREATE TABLE IF NOT EXISTS gpkg_extensions (table_name TEXT, column_name TEXT, extension_name TEXT NOT NULL, "
            "definition TEXT NOT NULL, scope TEXT NOT NULL, CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name))");
    sql.run("INSERT INTO gpkg_extensions (table_name, column_name, extension_name, definition, scope) VALUES (" +
            sql_literal(table) + ", " + sql_literal(column) +
            ", 'gpkg_rtree_index', 'http://www.geopackage.org/spec120/#extension_rtree', 'write-only')");
}

} // namespace trisnap
