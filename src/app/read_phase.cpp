// The read phase: the layer once, in input order, geometries to the spool (features.bin),
// one small entry per feature to records.bin, problems to runs of the store (problems-read-N,
// listed in read.bin).
#include "app/phases.hpp"

#include "app/collapse_guard.hpp"
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

/// What one layer's read goes into.
struct ReadTarget {
    ReadSummary& summary;
    stitch::FeatureSpool& spool;
    tiling::OutFile& records;
    Progress& progress;
    const InterruptGuard& interrupt;
    double tolerance;
};

// One layer, in input order; its problems are tagged with its index `k`.
void read_features(LayerReader& reader, std::uint32_t k, ReadTarget& to)
{
    ReadSummary& s = to.summary;
    LayerRead& layer = s.layers.emplace_back();
    std::vector<Problem> found; // one feature's
    char entry[RecordEntry::k_bytes];
    while (auto feature = reader.next()) {
        to.interrupt.check();
        found.clear();
        if (feature->problem) {
            found.push_back(*feature->problem);
        }
        RecordEntry e{feature->fid, RecordEntry::pass, false, static_cast<std::uint32_t>(feature->input_type)};
        if (feature->rejected) {
            e.verdict = RecordEntry::rejected;
            ++layer.rejected;
            to.spool.skip(feature->fid);
        } else if (feature->geometry) {
            e.verdict = RecordEntry::snap;
            layer.input_vertices += vertices_of(*feature->geometry);
            s.smaller += smaller_than_tolerance(*feature->geometry, to.tolerance) ? 1 : 0;
            ++layer.snapped;
            to.spool.add(s.records, feature->fid, *feature->geometry, found);
        } else {
            to.spool.skip(feature->fid);
        }
        e.problem = !found.empty();
        for (Problem& p : found) {
            p.layer = k;
            s.problems.add(std::move(p));
        }
        e.encode(entry);
        to.records.write(std::string_view(entry, sizeof entry));
        ++s.records;
        ++layer.records;
        to.progress.update(static_cast<std::int64_t>(s.records));
    }
    layer.problems = s.problems.in_layer(k);
    s.rejected += layer.rejected;
    s.input_vertices += layer.input_vertices;
}

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
        ReadTarget to{s, spool, *records, progress, interrupt, plan.tolerance};
        for (std::size_t k = 0; k < plan.layers.size(); ++k) {
            const IgnoredAttributes ignored(*plan.layers[k]);
            LayerReader reader(*plan.dataset, *plan.layers[k], plan.layers);
            if (k == 0) {
                progress.start("plan", plan.feature_count >= 0 ? plan.feature_count : reader.count_hint());
            }
            read_features(reader, static_cast<std::uint32_t>(k), to);
            if (plan.layers.size() > 1) {
                s.layers.back().fids_unique = spool.end_layer();
            }
        }
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
