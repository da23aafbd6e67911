// The write phase: the layer read again (attributes, pass-through geometries) in step with
// records.bin and the stitched features, written in input order. Nothing is held but the
// current feature (and the problems' bounded buffer); a difference between the two reads (the
// input changed meanwhile) stops it.
#include "app/phases.hpp"

#include "app/collapse_guard.hpp"
#include "app/command.hpp"
#include "app/handoff.hpp"

#include "io/gpkg_rows.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"
#include "io/reader.hpp"
#include "tiling/tile_input.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace trisnap {
namespace {

Problem feature_problem(std::uint32_t layer, std::int64_t fid, ProblemCode code, std::string message)
{
    Problem p;
    p.feature_id = fid;
    p.layer = layer;
    p.code = code;
    p.message = std::move(message);
    p.x = p.y = std::numeric_limits<double>::quiet_NaN();
    return p;
}

// records.bin, one entry at a time (read through a buffer).
class RecordLog {
public:
    explicit RecordLog(const tiling::WorkStore& store) : m_file(store.open(k_records_file)), m_in(*m_file) {}
    bool next(RecordEntry& e)
    {
        char buffer[RecordEntry::k_bytes];
        const std::size_t got = m_in.read(buffer, sizeof buffer);
        if (got == 0) {
            return false;
        }
        if (got != sizeof buffer) {
            throw tiling::work_error("damaged work file: records.bin is cut short");
        }
        e = RecordEntry::decode(buffer);
        return true;
    }

private:
    std::unique_ptr<tiling::InFile> m_file;
    tiling::BufferedReader m_in;
};

/// While a layer is read again for its attributes only (no feature of it passes through with
/// its own geometry), the driver is told to leave the geometries out too: GeoPackage then does
/// not fetch or decode them. Fields already left out stay left out (trisnap leaves none out
/// itself: --select chooses what is written, not what is read). Not with a spatial
/// filter (--bbox: the driver tests the geometries), nor for OSM (layers read interleaved).
class GeometriesLeftOut {
public:
    GeometriesLeftOut(Plan& plan, OGRLayer& layer, bool needed) : m_layer(layer)
    {
        if (needed || m_layer.GetSpatialFilter() != nullptr || std::string(plan.dataset->GetDriverName()) == "OSM") {
            return;
        }
        const OGRFeatureDefn* defn = m_layer.GetLayerDefn();
        for (int i = 0; i < defn->GetFieldCount(); ++i) {
            if (defn->GetFieldDefn(i)->IsIgnored()) {
                m_kept.emplace_back(defn->GetFieldDefn(i)->GetNameRef());
            }
        }
        if (defn->IsStyleIgnored()) {
            m_kept.emplace_back("OGR_STYLE");
        }
        m_active = set({"OGR_GEOMETRY"});
    }
    ~GeometriesLeftOut()
    {
        if (m_active) {
            set({});
        }
    }
    GeometriesLeftOut(const GeometriesLeftOut&) = delete;
    GeometriesLeftOut& operator=(const GeometriesLeftOut&) = delete;

private:
    bool set(std::vector<std::string> extra)
    {
        std::vector<const char*> names;
        for (const std::vector<std::string>* list : {&m_kept, &extra}) {
            for (const std::string& n : *list) {
                names.push_back(n.c_str());
            }
        }
        names.push_back(nullptr);
        return m_layer.SetIgnoredFields(names.data()) == OGRERR_NONE;
    }

    OGRLayer& m_layer;
    std::vector<std::string> m_kept; ///< fields left out before
    bool m_active = false;
};

/// One input feature's record and, when snapped, its stitched geometry: what the geometry side
/// of the phase prepares. Where OUT's layer takes GeoPackage rows (io/gpkg_rows.hpp) the
/// geometry is encoded there, into the blob the row binds: only the blob crosses to the writing
/// side. Otherwise the flat stitched geometry crosses and the writer makes, encodes and frees
/// its OGR geometry on its own core (REPORT.md, "The two vCPUs' pace"). The feature's attributes
/// (and a passed-through feature's own geometry) are read on the writing side, where they are
/// written: on two threads only the geometry moves between the cores.
/// The team's two vCPUs are far apart: while the attributes crossed too, each side took about
/// 40 % longer on its own thread than in one thread's loop (Andorra x43: reading 0.34 -> 0.48 s,
/// writing 0.20 -> 0.28 s, medians of 4), and the second thread gained nothing
/// (bench/results/REPORT.md, "The write phase split by what crosses").
struct Ready {
    std::uint32_t k = 0;                   ///< input layer
    std::size_t seq = 0;                   ///< input position across layers
    RecordEntry e;
    Geometry stitched;                     ///< a snapped feature's stitched geometry (no rows); empty: none
    bool as_row = false;                   ///< its GeoPackage row's blob is `row` (`stitched` unused)
    GpkgGeometry row;                      ///< the row's geometry blob; empty: none
    std::vector<Problem> problems;         ///< the stitched feature's
    std::size_t vertices = 0;              ///< of the geometry held (the handoff's weight)
    std::size_t weight() const { return vertices; } ///< what it holds in memory (app/handoff.hpp)
};

/// The handoff's weight of a blob: its bytes over a 2D vertex's.
std::size_t blob_vertices(const GpkgGeometry& g) { return g.blob.size() / 16; }

/// The geometry side: records.bin and the stitched features, in input order. It touches the
/// work store and the merger only.
class Stitched {
public:
    Stitched(const tiling::WorkStore& store, stitch::OutputMerger& merger, const LayerWriter& writer,
             const RunResult& result, const InterruptGuard& interrupt)
        : m_log(store), m_merger(merger), m_writer(writer), m_interrupt(interrupt)
    {
        for (const LayerCounts& c : result.layers) { // copied: the writing side updates the result
            m_input.push_back(c.input);
        }
    }
    /// The next input feature's, false after the last of the last layer.
    bool next(Ready& r);

private:
    RecordLog m_log;
    stitch::OutputMerger& m_merger;
    const LayerWriter& m_writer; ///< rows(): read only, set before the phase
    const InterruptGuard& m_interrupt;
    std::vector<std::size_t> m_input; ///< features of each layer read the first time
    std::uint32_t m_k = 0;            ///< the layer
    std::size_t m_i = 0;              ///< its features so far
    std::size_t m_seq = 0;            ///< input position across layers
    stitch::OutputItem m_item;
};

bool Stitched::next(Ready& r)
{
    while (m_k < m_input.size() && m_i >= m_input[m_k]) {
        ++m_k;
        m_i = 0;
    }
    if (m_k >= m_input.size()) {
        return false;
    }
    if (!m_log.next(r.e)) {
        throw tiling::work_error("damaged work file: records.bin is cut short");
    }
    m_interrupt.check();
    r.k = m_k;
    r.seq = m_seq++;
    ++m_i;
    if (r.e.verdict != RecordEntry::snap) {
        return true;
    }
    if (!m_merger.next(m_item) || m_item.seq != r.seq) {
        throw tiling::work_error("damaged work files: the stitched features do not line up with records.bin");
    }
    r.problems = std::move(m_item.problems);
    m_item.problems.clear();
    if (const GpkgRows* rows = m_writer.rows(r.k)) {
        encode_gpkg(m_item.output.geometry, static_cast<OGRwkbGeometryType>(r.e.type), rows->srs_id(), r.row);
        m_item.output.geometry = {};
        r.as_row = true;
        r.vertices = blob_vertices(r.row);
        return true;
    }
    r.stitched = std::move(m_item.output.geometry);
    m_item.output.geometry = {};
    r.vertices = tiling::engine_vertices(r.stitched);
    return true;
}

/// The input's layers read again, in step with the records, for the attributes (and the
/// geometries of the features that pass through): on the writing side. Which layer a record is
/// of, and where each layer ends, the records say (Stitched walks the counts of the first read).
class Attributes {
public:
    Attributes(Plan& plan, const RunResult& result) : m_plan(plan)
    {
        for (const LayerCounts& c : result.layers) {
            m_geometries_read.push_back(c.input != c.rejected + c.snapped);
        }
    }
    /// The next feature of layer `r.k`, which must be the one `r.e` records.
    OGRFeatureUniquePtr next(const Ready& r);
    /// After the last feature: every layer has ended where the first read ended.
    void finish() { close_through(static_cast<std::uint32_t>(m_geometries_read.size())); }

private:
    [[noreturn]] void changed(std::uint32_t k, const std::string& what) const
    {
        throw io_error(m_plan.input_path, m_plan.layers[k]->GetName(),
                       "the input changed while trisnap ran (" + what + "); run again on a stable copy");
    }
    void open_layer();
    /// Every layer before `k` read to its end, checked to have no more features.
    void close_through(std::uint32_t k);

    Plan& m_plan;
    std::vector<bool> m_geometries_read; ///< per layer: some pass through with their own geometry
    std::uint32_t m_k = 0; ///< the layer being read
    std::size_t m_i = 0;   ///< features of it read
    std::unique_ptr<GeometriesLeftOut> m_left_out;
    std::unique_ptr<LayerReader> m_reader;
};

void Attributes::open_layer()
{
    m_left_out = std::make_unique<GeometriesLeftOut>(m_plan, *m_plan.layers[m_k], m_geometries_read[m_k]);
    m_reader = std::make_unique<LayerReader>(*m_plan.dataset, *m_plan.layers[m_k], m_plan.layers);
    m_i = 0;
}

void Attributes::close_through(std::uint32_t k)
{
    while (m_k < k && m_k < m_geometries_read.size()) {
        if (!m_reader) {
            open_layer();
        }
        if (m_reader->next_raw()) {
            changed(m_k, "it now has more than " + std::to_string(m_i) + " features");
        }
        m_reader.reset(); // before the ignored fields change back
        m_left_out.reset();
        ++m_k;
    }
}

OGRFeatureUniquePtr Attributes::next(const Ready& r)
{
    close_through(r.k);
    if (!m_reader) {
        open_layer();
    }
    OGRFeatureUniquePtr f = m_reader->next_raw();
    if (!f) {
        changed(m_k, "it now ends after " + std::to_string(m_i) + " features");
    }
    if (f->GetFID() != r.e.fid) {
        changed(m_k, "feature " + std::to_string(r.seq + 1) + " has FID " + std::to_string(f->GetFID()) + ", was " +
                         std::to_string(r.e.fid));
    }
    ++m_i;
    return f;
}

/// The writing side: the input read again for the attributes, OUT's writer and the run's
/// counts and problems.
class Writer {
public:
    Writer(Plan& plan, LayerWriter& writer, RunResult& result)
        : m_attributes(plan, result), m_writer(writer), m_result(result), m_rejected(rejected_features(result.problems))
    {
    }
    /// Features written so far, in all layers.
    std::size_t written() const { return m_writer.written(); }
    void feature(Ready& r);
    /// After the last feature: the input's layers ended where they did the first time.
    void finish() { m_attributes.finish(); }
    /// Accounts the rows OUT's writer refused since the last call.
    void refusals();

private:
    void write(std::uint32_t k, std::int64_t fid, OGRFeature& f, std::unique_ptr<OGRGeometry>& geometry);
    void write_row(std::uint32_t k, const OGRFeature& f, std::int64_t fid, const GpkgGeometry& row);
    void account(std::uint32_t k, std::int64_t fid, const std::string& error);
    void vanished(std::uint32_t k, const RecordEntry& e, bool reported, bool rejected);

    Attributes m_attributes;
    LayerWriter& m_writer;
    RunResult& m_result;
    std::set<std::pair<std::uint32_t, std::int64_t>> m_rejected; ///< (layer, FID) the engine rejected (109)
    GpkgValues m_values;  ///< a row's values, taken again for each row
    GpkgGeometry m_own;   ///< a passed-through feature's own geometry, encoded
};

// The values the format changed (903) go to the log as they are found, not held by the writer
// until the end (their order in the log is the same: no other phase reports those codes).
void Writer::write(std::uint32_t k, std::int64_t fid, OGRFeature& f, std::unique_ptr<OGRGeometry>& geometry)
{
    account(k, fid, m_writer.write_lending(k, f, fid, geometry));
}

// A row goes in with its batch: the refusals of earlier rows may come back now (problem 902 is
// sorted into place with the others: app/problem_log.hpp).
void Writer::write_row(std::uint32_t k, const OGRFeature& f, std::int64_t fid, const GpkgGeometry& row)
{
    m_writer.rows(k)->take(f, fid, m_values);
    m_writer.write_row(k, m_values, row);
    refusals();
}

void Writer::refusals()
{
    for (LayerWriter::Refusal& r : m_writer.take_refusals()) {
        account(static_cast<std::uint32_t>(r.layer), r.fid, r.message);
    }
}

// A feature handed to OUT's writer: refused (`error`: problem 902), or written with the values
// the format changed.
void Writer::account(std::uint32_t k, std::int64_t fid, const std::string& error)
{
    if (!error.empty()) {
        ++m_result.unwritable;
        ++m_result.layers[k].unwritable;
        m_result.problems.add(feature_problem(k, fid, ProblemCode::unwritable_feature, error));
    }
    for (Problem& p : m_writer.take_problems()) {
        m_result.problems.add(std::move(p));
    }
}

// A feature the engine returned empty: a problem says why, unless the read or the engine has
// said something about it already (`reported`); `rejected`: the engine refused it (109), which
// the collapse guard counts apart from collapses.
void Writer::vanished(std::uint32_t k, const RecordEntry& e, bool reported, bool rejected)
{
    ++m_result.dropped;
    ++m_result.layers[k].dropped;
    if (rejected) {
        ++m_result.dropped_rejected;
    }
    if (!reported) {
        const auto type = static_cast<OGRwkbGeometryType>(e.type);
        m_result.problems.add(feature_problem(k, e.fid, type == wkbPolygon || type == wkbMultiPolygon
            ? ProblemCode::collapsed_polygon : ProblemCode::collapsed_line, "the feature vanished when snapped; not written"));
    }
}

void Writer::feature(Ready& r)
{
    const std::uint32_t k = r.k;
    const RecordEntry& e = r.e;
    OGRFeatureUniquePtr f = m_attributes.next(r); // read for every record: the reads stay in step
    if (e.verdict == RecordEntry::rejected) {
        return;
    }
    const GpkgRows* rows = m_writer.rows(k);
    if (e.verdict == RecordEntry::pass) {
        std::unique_ptr<OGRGeometry> own(f->StealGeometry());
        if (rows != nullptr && encode_gpkg(own.get(), rows->srs_id(), m_own)) {
            write_row(k, *f, e.fid, m_own);
        } else {
            write(k, e.fid, *f, own);
        }
        return;
    }
    const bool reported = e.problem || !r.problems.empty();
    const bool rejected = m_rejected.count({k, e.fid}) > 0 ||
                          std::any_of(r.problems.begin(), r.problems.end(), rejected_by_engine);
    for (Problem& p : r.problems) {
        p.layer = k;
        m_result.problems.add(std::move(p));
    }
    if (r.as_row ? r.row.blob.empty() : r.stitched.empty()) {
        vanished(k, e, reported, rejected);
        return;
    }
    f->SetGeometryDirectly(nullptr);
    if (r.as_row) {
        write_row(k, *f, e.fid, r.row);
        return;
    }
    std::unique_ptr<OGRGeometry> g(to_ogr(r.stitched, static_cast<OGRwkbGeometryType>(e.type)));
    write(k, e.fid, *f, g);
}

/// Whether the write phase hands features to a writer thread (app/handoff.hpp). It pays where
/// a feature's fixed cost (its SQLite row, its attributes) outweighs its vertices, and loses
/// where features are large. Since the attributes are read on the writing side (only the blobs
/// cross), measured 2026-12-02 at 2 threads, interleaved, thread on against off: write phase
/// 0.14-0.15 against 0.16-0.20 s on Jakarta buildings (5 vertices a feature, 6 of 6 pairs),
/// 0.59-0.63 against 0.77-0.81 s on Andorra x43 (7.7, 5 of 5), and 0.32-0.35 against 0.20-0.28 s
/// on Natural Earth land (39: nearly all its work is stitching, which a thread of its own did not
/// make faster; 5 of 5 lost). Earlier measurements, with the
/// attributes crossing too: bench/results/REPORT.md, "A writer thread", "GeoPackage rows" and
/// "The write phase split by what crosses".
bool writer_thread_pays(const Plan& plan, const RunResult& result)
{
    constexpr std::size_t k_most_vertices_per_feature = 16;
    const int threads = plan.tiling.threads > 0 ? plan.tiling.threads : available_cores();
    return threads >= 2 && result.input_vertices <= k_most_vertices_per_feature * result.input;
}

} // namespace

void write_layer(Plan& plan, const tiling::WorkStore& store, stitch::OutputMerger& merger, LayerWriter& writer,
                 RunResult& result, Progress& progress, const InterruptGuard& interrupt)
{
    result.problems.begin_phase("problems-write-"); // runs of a write that stopped go
    Stitched input(store, merger, writer, result, interrupt);
    Writer w(plan, writer, result);
    for (std::size_t k = 0; k < result.layers.size(); ++k) {
        writer.expect(k, result.layers[k].input);
    }
    // The count is what went into OUT, of the features read: a bar at 292/292 for a layer that
    // collapsed entirely (--force) said "written" of features that were not.
    progress.start("write", static_cast<std::int64_t>(result.input), "features written");
    // The stitched features (encoded) on one side; the input's attributes read again and OUT
    // written on the other: on two threads at once when the run has them and it pays
    // (app/handoff.hpp); the features reach OUT in input order either way.
    const auto t0 = std::chrono::steady_clock::now();
    hand_off<Ready>(writer_thread_pays(plan, result), HandoffShape{}, [&](Ready& r) { return input.next(r); },
                    [&](Ready& r) {
                        w.feature(r);
                        progress.update(static_cast<std::int64_t>(w.written()));
                    });
    w.finish();
    writer.flush_rows(); // the last batch of rows
    const auto t1 = std::chrono::steady_clock::now();
    w.refusals();
    progress.finish(static_cast<std::int64_t>(w.written()));
    interrupt.check();
    // Before OUT is committed: nothing goes into place. Features of failed tiles (303) are not
    // collapses: they are reported, and --on-error skip asked for them to be left out.
    const std::size_t failed = merger.counts().failed;
    check_collapse(plan, Drops{result.dropped - failed - result.dropped_rejected, result.dropped_rejected}, result.input);
    writer.commit();
    const auto t2 = std::chrono::steady_clock::now();
    spdlog::debug("write: features {:.3f} s, commit {:.3f} s", std::chrono::duration<double>(t1 - t0).count(),
                  std::chrono::duration<double>(t2 - t1).count());
    for (Problem& p : writer.take_problems()) {
        result.problems.add(std::move(p)); // values and field names the format changed
    }
    for (const std::string& line : writer.warnings()) {
        spdlog::warn("{}: {}", plan.write.path, line); // one line per field and kind, not per feature
    }
    result.written = writer.written();
    for (std::size_t k = 0; k < result.layers.size(); ++k) {
        result.layers[k].written = writer.written(k);
    }
}

} // namespace trisnap
