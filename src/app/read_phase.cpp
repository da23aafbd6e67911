// The read phase: the layer once, in input order, geometries to the spool (features.bin),
// one small entry per feature to records.bin, problems to runs of the store (problems-read-N,
// listed in read.bin).
#include "app/phases.hpp"

#include "app/collapse_guard.hpp"
#include "app/command.hpp"
#include "app/handoff.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"
#include "io/reader.hpp"
#include "stitch/layout.hpp"
#include "tiling/records.hpp"

#include <cstring>

namespace trisnap {
namespace {

const char* const k_read = "read.bin";
const char* const k_read_problems = "problems-read-"; ///< the read phase's problem runs

std::size_t vertices_of(const Geometry& g)
{
    std::size_t n = 0;
    for (const Polygon& p : g.polygons) {
        for (const Path& r : p.rings) {
            n += r.size();
        }
    }
    for (const Path& l : g.lines) {
        n += l.size();
    }
    return n;
}

// Attributes are not needed until the write phase: the driver need not parse them now.
class IgnoredAttributes {
public:
    explicit IgnoredAttributes(OGRLayer& layer) : m_layer(layer)
    {
        const OGRFeatureDefn* defn = layer.GetLayerDefn();
        std::vector<const char*> names;
        for (int i = 0; i < defn->GetFieldCount(); ++i) {
            names.push_back(defn->GetFieldDefn(i)->GetNameRef());
        }
        names.push_back("OGR_STYLE");
        names.push_back(nullptr);
        layer.SetIgnoredFields(names.data());
    }
    ~IgnoredAttributes() { m_layer.SetIgnoredFields(nullptr); }
    IgnoredAttributes(const IgnoredAttributes&) = delete;
    IgnoredAttributes& operator=(const IgnoredAttributes&) = delete;

private:
    OGRLayer& m_layer;
};

void save_read(tiling::WorkStore& store, const ReadSummary& s)
{
    std::string bytes;
    tiling::ByteWriter w(bytes);
    w.put<std::uint64_t>(s.records);
    w.put<std::uint64_t>(s.rejected);
    w.put<std::uint64_t>(s.input_vertices);
    s.problems.save(w);
    // The meta (with the plan's sample, up to 256 MiB) is spool.meta's: kept once.
    w.put<std::uint64_t>(s.layers.size());
    for (const LayerRead& l : s.layers) {
        for (std::uint64_t v : {l.records, l.rejected, l.input_vertices, l.snapped, l.problems}) {
            w.put<std::uint64_t>(v);
        }
        w.put<std::uint8_t>(l.fids_unique ? 1 : 0);
    }
    store.put(k_read, bytes);
}

/// What the reading side hands over: a feature of layer `k`, or where a layer starts or ends.
struct ReadItem {
    enum Kind : std::uint8_t { feature, layer_start, layer_end };
    Kind kind = feature;
    std::uint32_t k = 0;
    std::optional<InputFeature> read;  ///< kind feature
    std::size_t vertices = 0;          ///< of its geometry to snap
    bool smaller = false;              ///< that geometry is smaller than the tolerance
    std::int64_t count_hint = -1;      ///< kind layer_start: the driver's count of the layer
    std::size_t weight() const { return vertices; } ///< what it holds in memory (app/handoff.hpp)
};

/// The reading side: the layers one after the other, in input order, each feature read,
/// classified and measured. It touches the input dataset only.
class LayerFeed {
public:
    LayerFeed(Plan& plan, const InterruptGuard& interrupt) : m_plan(plan), m_interrupt(interrupt) {}
    bool next(ReadItem& item)
    {
        if (m_k >= m_plan.layers.size()) {
            return false;
        }
        item.k = static_cast<std::uint32_t>(m_k);
        if (!m_reader) {
            m_ignored = std::make_unique<IgnoredAttributes>(*m_plan.layers[m_k]);
            m_reader = std::make_unique<LayerReader>(*m_plan.dataset, *m_plan.layers[m_k], m_plan.layers);
            item.kind = ReadItem::layer_start;
            item.count_hint = m_k == 0 && m_plan.feature_count < 0 ? m_reader->count_hint() : m_plan.feature_count;
            return true;
        }
        m_interrupt.check();
        item.read = m_reader->next();
        if (!item.read) {
            m_reader.reset();
            m_ignored.reset();
            ++m_k;
            item.kind = ReadItem::layer_end;
            return true;
        }
        item.read->feature.reset(); // attributes are read again when writing
        if (item.read->geometry) {
            item.vertices = vertices_of(*item.read->geometry);
            item.smaller = smaller_than_tolerance(*item.read->geometry, m_plan.tolerance);
        }
        return true;
    }

private:
    Plan& m_plan;
    const InterruptGuard& m_interrupt;
    std::size_t m_k = 0;
    std::unique_ptr<IgnoredAttributes> m_ignored;
    std::unique_ptr<LayerReader> m_reader;
};

/// The consuming side: the spool, records.bin, the summary and its problems.
class ReadSink {
public:
    ReadSink(ReadSummary& summary, stitch::FeatureSpool& spool, tiling::OutFile& records, Progress& progress, bool layers)
        : m_summary(summary), m_spool(spool), m_records(records), m_progress(progress), m_several_layers(layers)
    {
    }
    void take(ReadItem& item)
    {
        switch (item.kind) {
        case ReadItem::layer_start:
            m_summary.layers.emplace_back();
            if (item.k == 0) {
                m_progress.start("plan", item.count_hint);
            }
            return;
        case ReadItem::layer_end:
            end_layer(item.k);
            return;
        case ReadItem::feature:
            feature(item);
            return;
        }
    }

private:
    // One feature, in input order; its problems are tagged with its layer's index.
    void feature(ReadItem& item)
    {
        ReadSummary& s = m_summary;
        LayerRead& layer = s.layers.back();
        InputFeature& in = *item.read;
        m_found.clear();
        if (in.problem) {
            m_found.push_back(*in.problem);
        }
        RecordEntry e{in.fid, RecordEntry::pass, false, static_cast<std::uint32_t>(in.input_type)};
        if (in.rejected) {
            e.verdict = RecordEntry::rejected;
            ++layer.rejected;
            m_spool.skip(in.fid);
        } else if (in.geometry) {
            e.verdict = RecordEntry::snap;
            layer.input_vertices += item.vertices;
            s.smaller += item.smaller ? 1 : 0;
            ++layer.snapped;
            m_spool.add(s.records, in.fid, *in.geometry, m_found);
        } else {
            m_spool.skip(in.fid);
        }
        e.problem = !m_found.empty();
        for (Problem& p : m_found) {
            p.layer = item.k;
            s.problems.add(std::move(p));
        }
        char entry[RecordEntry::k_bytes];
        e.encode(entry);
        m_records.write(std::string_view(entry, sizeof entry));
        ++s.records;
        ++layer.records;
        m_progress.update(static_cast<std::int64_t>(s.records));
    }

    void end_layer(std::uint32_t k)
    {
        ReadSummary& s = m_summary;
        LayerRead& layer = s.layers.back();
        layer.problems = s.problems.in_layer(k);
        s.rejected += layer.rejected;
        s.input_vertices += layer.input_vertices;
        if (m_several_layers) {
            layer.fids_unique = m_spool.end_layer();
        }
    }

    ReadSummary& m_summary;
    stitch::FeatureSpool& m_spool;
    tiling::OutFile& m_records;
    Progress& m_progress;
    bool m_several_layers;
    std::vector<Problem> m_found; ///< one feature's
};

} // namespace

ReadSummary read_layer(Plan& plan, tiling::WorkStore& store, const ReadBuffers& buffers, Progress& progress,
                       const InterruptGuard& interrupt)
{
    ReadSummary s;
    s.problems = ProblemLog(store, k_read_problems, buffers.problem_bytes);
    s.problems.begin_phase(k_read_problems); // an earlier attempt's runs go
    {
        stitch::FeatureSpool spool(store, plan.options.tolerance, buffers.sample_vertices, buffers.fids);
        const std::unique_ptr<tiling::OutFile> records = store.create(k_records_file);
        // Reading and classifying on one side, cleaning and spooling on the other: on two
        // threads at once when the run has them (app/handoff.hpp), in input order either way.
        LayerFeed feed(plan, interrupt);
        ReadSink sink(s, spool, *records, progress, plan.layers.size() > 1);
        hand_off<ReadItem>(io_on_two_threads(plan), HandoffShape{}, [&](ReadItem& item) { return feed.next(item); },
                           [&](ReadItem& item) { sink.take(item); });
        progress.finish();
        records->commit();
        s.meta = spool.finish();
        if (plan.layers.size() == 1) {
            s.layers[0].fids_unique = s.meta.fids_unique;
        }
    }
    check_read(plan, s.records, s.smaller);
    s.problems.seal();
    save_read(store, s);
    return s;
}

bool io_on_two_threads(const Plan& plan)
{
    const int threads = plan.tiling.threads > 0 ? plan.tiling.threads : available_cores();
    return threads >= 2;
}

void check_read(const Plan& plan, std::size_t features, std::size_t smaller)
{
    if (features == 0) {
        throw io_error(input_label(plan), "",
                       plan.layer->GetAttrQueryString() || plan.layer->GetSpatialFilter()
                           ? "no feature matches --where/--bbox: nothing to snap"
                           : "the layer is empty: nothing to snap");
    }
    check_collapse(plan, Drops{smaller, 0}, features, true);
}

std::size_t InputSurvey::total() const
{
    std::size_t n = 0;
    for (std::size_t f : features) {
        n += f;
    }
    return n;
}

InputSurvey survey_input(Plan& plan)
{
    InputSurvey survey;
    for (OGRLayer* layer : plan.layers) {
        const IgnoredAttributes ignored(*layer);
        LayerReader reader(*plan.dataset, *layer, plan.layers);
        std::size_t& features = survey.features.emplace_back(0);
        for (OGRFeatureUniquePtr f = reader.next_raw(); f; f = reader.next_raw()) {
            ++features;
            survey.vertices += count_vertices(f->GetGeometryRef());
            const InputFeature in = classify_feature(std::move(f));
            survey.smaller += in.geometry && smaller_than_tolerance(*in.geometry, plan.tolerance) ? 1 : 0;
        }
    }
    return survey;
}

bool load_read(tiling::WorkStore& store, std::size_t problem_bytes, ReadSummary& out)
{
    if (!store.exists(k_read)) {
        return false;
    }
    const std::string bytes = store.get(k_read);
    tiling::ByteReader r(bytes, "read summary");
    out.records = r.get<std::uint64_t>();
    out.rejected = r.get<std::uint64_t>();
    out.input_vertices = r.get<std::uint64_t>();
    out.problems = ProblemLog(store, k_read_problems, problem_bytes);
    out.problems.load(r);
    {
        const std::string meta = store.get(stitch::files::spool_meta);
        tiling::ByteReader m(meta, "spool meta");
        out.meta = stitch::SpoolMeta::load(m);
    }
    out.layers.resize(r.get<std::uint64_t>());
    for (LayerRead& l : out.layers) {
        for (std::uint64_t* v : {&l.records, &l.rejected, &l.input_vertices, &l.snapped, &l.problems}) {
            *v = r.get<std::uint64_t>();
        }
        l.fids_unique = r.get<std::uint8_t>() != 0;
    }
    return true;
}

void RecordEntry::encode(char* out) const
{
    std::memcpy(out, &fid, sizeof fid);
    out[8] = static_cast<char>(verdict | (problem ? 0x80 : 0));
    std::memcpy(out + 9, &type, sizeof type);
}

RecordEntry RecordEntry::decode(const char* in)
{
    RecordEntry e;
    std::memcpy(&e.fid, in, sizeof e.fid);
    const auto byte = static_cast<std::uint8_t>(in[8]);
    e.verdict = static_cast<Verdict>(byte & 0x7f);
    e.problem = (byte & 0x80) != 0;
    std::memcpy(&e.type, in + 9, sizeof e.type);
    return e;
}

} // namespace trisnap
