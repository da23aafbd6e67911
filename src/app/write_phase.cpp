// The write phase: the layer read again (attributes, pass-through geometries) in step with
// records.bin and the stitched features, written in input order. Nothing is held but the
// current feature (and the problems' bounded buffer); a difference between the two reads (the
// input changed meanwhile) stops it.
#include "app/phases.hpp"

#include "app/collapse_guard.hpp"

#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"
#include "io/reader.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
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

// records.bin, one entry at a time.
class RecordLog {
public:
    explicit RecordLog(const tiling::WorkStore& store) : m_file(store.open(k_records_file)) {}
    bool next(RecordEntry& e)
    {
        char buffer[RecordEntry::k_bytes];
        std::size_t got = 0;
        while (got < sizeof buffer) {
            const std::size_t k = m_file->read(buffer + got, sizeof buffer - got);
            if (k == 0) {
                break;
            }
            got += k;
        }
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
};

class Writer {
public:
    Writer(Plan& plan, stitch::OutputMerger& merger, LayerWriter& writer, RunResult& result)
        : m_plan(plan), m_merger(merger), m_writer(writer), m_result(result),
          m_rejected(rejected_features(result.problems))
    {
    }
    /// Features written so far, in all layers.
    std::size_t written() const { return m_writer.written(); }
    /// Feature `seq` (input position across all layers) of input layer `k`.
    void feature(std::uint32_t k, std::size_t seq, const RecordEntry& e, OGRFeatureUniquePtr f);
    [[noreturn]] void changed(std::uint32_t k, const std::string& what) const
    {
        throw io_error(m_plan.input_path, m_plan.layers[k]->GetName(),
                       "the input changed while trisnap ran (" + what + "); run again on a stable copy");
    }

private:
    void write(std::uint32_t k, std::int64_t fid, OGRFeature& f, OGRGeometry* geometry);
    void vanished(std::uint32_t k, const RecordEntry& e, bool reported, bool rejected);

    Plan& m_plan;
    stitch::OutputMerger& m_merger;
    LayerWriter& m_writer;
    RunResult& m_result;
    std::set<std::pair<std::uint32_t, std::int64_t>> m_rejected; ///< (layer, FID) the engine rejected (109)
    stitch::OutputItem m_item;
};

// The values the format changed (903) go to the log as they are found, not held by the writer
// until the end (their order in the log is the same: no other phase reports those codes).
void Writer::write(std::uint32_t k, std::int64_t fid, OGRFeature& f, OGRGeometry* geometry)
{
    if (std::string error = m_writer.write(k, f, fid, geometry); !error.empty()) {
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

void Writer::feature(std::uint32_t k, std::size_t seq, const RecordEntry& e, OGRFeatureUniquePtr f)
{
    if (f->GetFID() != e.fid) {
        changed(k, "feature " + std::to_string(seq + 1) + " has FID " + std::to_string(f->GetFID()) + ", was " + std::to_string(e.fid));
    }
    if (e.verdict == RecordEntry::rejected) {
        return;
    }
    if (e.verdict == RecordEntry::pass) {
        OGRGeometry* g = f->StealGeometry();
        write(k, e.fid, *f, g);
        return;
    }
    if (!m_merger.next(m_item) || m_item.seq != seq) {
        changed(k, "the stitched features do not line up with the input");
    }
    const bool reported = e.problem || !m_item.problems.empty();
    const bool rejected = m_rejected.count({k, e.fid}) > 0 ||
                          std::any_of(m_item.problems.begin(), m_item.problems.end(), rejected_by_engine);
    for (Problem& p : m_item.problems) {
        p.layer = k;
        m_result.problems.add(std::move(p));
    }
    if (m_item.output.geometry.empty()) {
        vanished(k, e, reported, rejected);
        return;
    }
    f->SetGeometryDirectly(nullptr);
    write(k, e.fid, *f, to_ogr(m_item.output.geometry, static_cast<OGRwkbGeometryType>(e.type)));
}

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

/// Input layer `k` read again, in step with its `count` entries of records.bin; `seq` is the
/// input position of its first feature, and the position after its last is returned.
std::size_t write_features(Plan& plan, std::uint32_t k, const LayerCounts& counts, std::size_t seq, RecordLog& log,
                           Writer& w, Progress& progress, const InterruptGuard& interrupt)
{
    const std::size_t count = counts.input;
    const GeometriesLeftOut left_out(plan, *plan.layers[k], counts.input != counts.rejected + counts.snapped);
    LayerReader reader(*plan.dataset, *plan.layers[k], plan.layers);
    RecordEntry e;
    for (std::size_t i = 0; i < count; ++i, ++seq) {
        if (!log.next(e)) {
            throw tiling::work_error("damaged work file: records.bin is cut short");
        }
        interrupt.check();
        OGRFeatureUniquePtr f = reader.next_raw();
        if (!f) {
            w.changed(k, "it now ends after " + std::to_string(i) + " features");
        }
        w.feature(k, seq, e, std::move(f));
        progress.update(static_cast<std::int64_t>(w.written()));
    }
    if (reader.next_raw()) {
        w.changed(k, "it now has more than " + std::to_string(count) + " features");
    }
    return seq;
}

} // namespace

void write_layer(Plan& plan, const tiling::WorkStore& store, stitch::OutputMerger& merger, LayerWriter& writer,
                 RunResult& result, Progress& progress, const InterruptGuard& interrupt)
{
    RecordLog log(store);
    result.problems.begin_phase("problems-write-"); // runs of a write that stopped go
    Writer w(plan, merger, writer, result);
    // The count is what went into OUT, of the features read: a bar at 292/292 for a layer that
    // collapsed entirely (--force) said "written" of features that were not.
    progress.start("write", static_cast<std::int64_t>(result.input), "features written");
    std::size_t seq = 0;
    for (std::size_t k = 0; k < plan.layers.size(); ++k) {
        seq = write_features(plan, static_cast<std::uint32_t>(k), result.layers[k], seq, log, w, progress, interrupt);
    }
    progress.finish(static_cast<std::int64_t>(w.written()));
    interrupt.check();
    // Before OUT is committed: nothing goes into place. Features of failed tiles (303) are not
    // collapses: they are reported, and --on-error skip asked for them to be left out.
    const std::size_t failed = merger.counts().failed;
    check_collapse(plan, Drops{result.dropped - failed - result.dropped_rejected, result.dropped_rejected}, result.input);
    writer.commit();
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
