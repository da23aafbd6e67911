// The read phase: the layer once, in input order, geometries to the spool (features.bin),
// one small entry per feature to records.bin, problems kept in read.bin.
#include "app/phases.hpp"

#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"
#include "io/reader.hpp"
#include "tiling/records.hpp"

#include <cstring>

namespace trisnap {
namespace {

const char* const k_read = "read.bin";

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
    w.put<std::uint64_t>(s.problems.size());
    for (const Problem& p : s.problems) {
        tiling::put_problem(w, p);
    }
    s.meta.save(w);
    store.put(k_read, bytes);
}

} // namespace

ReadSummary read_layer(Plan& plan, tiling::WorkStore& store, std::size_t sample_cap, std::size_t fid_buffer,
                       Progress& progress, const InterruptGuard& interrupt)
{
    ReadSummary s;
    {
        const IgnoredAttributes ignored(*plan.layer);
        LayerReader reader(*plan.dataset, *plan.layer);
        stitch::FeatureSpool spool(store, plan.options.tolerance, sample_cap, fid_buffer);
        const std::unique_ptr<tiling::OutFile> records = store.create(k_records_file);
        progress.start("plan", plan.feature_count >= 0 ? plan.feature_count : reader.count_hint());
        char entry[RecordEntry::k_bytes];
        while (auto feature = reader.next()) {
            interrupt.check();
            if (feature->problem) {
                s.problems.push_back(*feature->problem);
            }
            RecordEntry e{feature->fid, RecordEntry::pass, static_cast<std::uint32_t>(feature->input_type)};
            if (feature->rejected) {
                e.verdict = RecordEntry::rejected;
                ++s.rejected;
                spool.skip(feature->fid);
            } else if (feature->geometry) {
                e.verdict = RecordEntry::snap;
                s.input_vertices += vertices_of(*feature->geometry);
                spool.add(s.records, feature->fid, *feature->geometry, s.problems);
            } else {
                spool.skip(feature->fid);
            }
            e.encode(entry);
            records->write(std::string_view(entry, sizeof entry));
            ++s.records;
            progress.update(static_cast<std::int64_t>(s.records));
        }
        progress.finish();
        records->commit();
        s.meta = spool.finish();
    }
    if (s.records == 0) {
        throw io_error(plan.input_path, plan.layer->GetName(),
                       plan.layer->GetAttrQueryString() || plan.layer->GetSpatialFilter()
                           ? "no feature matches --where/--bbox: nothing to snap"
                           : "the layer is empty: nothing to snap");
    }
    save_read(store, s);
    return s;
}

bool load_read(const tiling::WorkStore& store, ReadSummary& out)
{
    if (!store.exists(k_read)) {
        return false;
    }
    const std::string bytes = store.get(k_read);
    tiling::ByteReader r(bytes, "read summary");
    out.records = r.get<std::uint64_t>();
    out.rejected = r.get<std::uint64_t>();
    out.input_vertices = r.get<std::uint64_t>();
    out.problems.resize(r.get<std::uint64_t>());
    for (Problem& p : out.problems) {
        p = tiling::get_problem(r);
    }
    out.meta = stitch::SpoolMeta::load(r);
    return true;
}

void RecordEntry::encode(char* out) const
{
    std::memcpy(out, &fid, sizeof fid);
    out[8] = static_cast<char>(verdict);
    std::memcpy(out + 9, &type, sizeof type);
}

RecordEntry RecordEntry::decode(const char* in)
{
    RecordEntry e;
    std::memcpy(&e.fid, in, sizeof e.fid);
    e.verdict = static_cast<Verdict>(in[8]);
    std::memcpy(&e.type, in + 9, sizeof e.type);
    return e;
}

} // namespace trisnap
