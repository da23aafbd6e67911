// The read pass's side of the work directory: features.bin, features.idx, spool.meta, and the
// check that the FIDs are unique (sorted runs of FIDs spilled to the store when they outgrow
// their buffer, merged at the end).
#include "stitch/spool.hpp"

#include "tiling/records.hpp"
#include "tiling/tile_input.hpp"

#include <algorithm>
#include <queue>
#include <stdexcept>

namespace trisnap::stitch {
namespace {

constexpr std::int64_t k_null_fid = -1; // OGRNullFID

std::string fid_run(std::size_t k) { return "fids-" + std::to_string(k); }

// Merges the sorted runs (and the sorted buffer) and looks for two equal neighbours.
bool unique_across_runs(tiling::WorkStore& store, std::size_t runs, std::vector<std::int64_t>& buffer)
{
    std::sort(buffer.begin(), buffer.end());
    if (std::adjacent_find(buffer.begin(), buffer.end()) != buffer.end()) {
        return false;
    }
    if (runs == 0) {
        return true;
    }
    std::vector<std::unique_ptr<tiling::InFile>> files;
    std::vector<std::unique_ptr<tiling::BufferedReader>> readers; // 16 KiB each: 2,048 FIDs a read
    using Head = std::pair<std::int64_t, std::size_t>;
    std::priority_queue<Head, std::vector<Head>, std::greater<>> heap;
    auto pull = [&](std::size_t k) {
        std::int64_t v = 0;
        if (readers[k]->read(reinterpret_cast<char*>(&v), sizeof v) == sizeof v) {
            heap.emplace(v, k);
        }
    };
    for (std::size_t k = 0; k < runs; ++k) {
        files.push_back(store.open(fid_run(k)));
        readers.push_back(std::make_unique<tiling::BufferedReader>(*files.back(), std::size_t{16} << 10));
        pull(k);
    }
    std::size_t next_in_buffer = 0;
    bool have_last = false;
    std::int64_t last = 0;
    auto see = [&](std::int64_t v) {
        const bool repeated = have_last && v == last;
        have_last = true;
        last = v;
        return !repeated;
    };
    while (!heap.empty() || next_in_buffer < buffer.size()) {
        const bool from_buffer = heap.empty() || (next_in_buffer < buffer.size() && buffer[next_in_buffer] < heap.top().first);
        std::int64_t v = 0;
        if (from_buffer) {
            v = buffer[next_in_buffer++];
        } else {
            const Head h = heap.top();
            heap.pop();
            v = h.first;
            pull(h.second);
        }
        if (!see(v)) {
            return false;
        }
    }
    return true;
}

} // namespace

void SpoolMeta::save(tiling::ByteWriter& w, bool with_sample) const
{
    w.put(records);
    w.put(spooled);
    w.put(vertices);
    w.put<std::uint8_t>(fids_unique ? 1 : 0);
    for (double v : {sample.extent.xmin, sample.extent.ymin, sample.extent.xmax, sample.extent.ymax}) {
        w.put(v);
    }
    w.put<std::uint64_t>(sample.vertices);
    w.put<std::int32_t>(sample.level);
    const std::size_t kept = with_sample ? sample.xs.size() : 0;
    w.put<std::uint64_t>(kept);
    for (std::size_t i = 0; i < kept; ++i) {
        w.put(sample.xs[i]);
        w.put(sample.ys[i]);
    }
    w.put(largest_vertices);
    w.put(largest_fid);
}

SpoolMeta SpoolMeta::load(tiling::ByteReader& r)
{
    SpoolMeta m;
    m.records = r.get<std::uint64_t>();
    m.spooled = r.get<std::uint64_t>();
    m.vertices = r.get<std::uint64_t>();
    m.fids_unique = r.get<std::uint8_t>() != 0;
    m.sample.extent.xmin = r.get<double>();
    m.sample.extent.ymin = r.get<double>();
    m.sample.extent.xmax = r.get<double>();
    m.sample.extent.ymax = r.get<double>();
    m.sample.vertices = r.get<std::uint64_t>();
    m.sample.level = r.get<std::int32_t>();
    const auto n = r.get<std::uint64_t>();
    if (n > r.remaining() / (2 * sizeof(double))) {
        throw tiling::record_error("damaged work file: truncated spool meta record");
    }
    m.sample.xs.reserve(n);
    m.sample.ys.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) {
        m.sample.xs.push_back(r.get<double>());
        m.sample.ys.push_back(r.get<double>());
    }
    m.largest_vertices = r.get<std::uint64_t>();
    m.largest_fid = r.get<std::int64_t>();
    return m;
}

struct FeatureSpool::Impl {
    Impl(tiling::WorkStore& s, double t, std::size_t sample_cap, std::size_t fid_buffer)
        : store(s), tolerance(t), sample(sample_cap), fid_cap(std::max<std::size_t>(fid_buffer, 1024)),
          features(s.create(files::features)), offsets(s.create(files::offsets)), writer(*features)
    {
    }
    void note_fid(std::int64_t fid)
    {
        if (fid == k_null_fid) {
            layer_unique = false;
        }
        if (!layer_unique) {
            return;
        }
        fids.push_back(fid);
        if (fids.size() >= fid_cap) {
            std::sort(fids.begin(), fids.end());
            if (std::adjacent_find(fids.begin(), fids.end()) != fids.end()) {
                layer_unique = false;
            }
            store.put(fid_run(runs++), std::string_view(reinterpret_cast<const char*>(fids.data()), fids.size() * sizeof(std::int64_t)));
            fids.clear();
        }
    }

    void write_record(std::string_view bytes)
    {
        const std::uint64_t offset = writer.write(bytes);
        offsets->write(std::string_view(reinterpret_cast<const char*>(&offset), sizeof offset));
    }

    // Whether the current layer's FIDs were unique, and the check's state reset for the next.
    bool end_layer()
    {
        const bool unique = layer_unique && unique_across_runs(store, runs, fids);
        store.remove_all("fids-");
        fids.clear();
        runs = 0;
        layer_unique = true;
        ++layers_ended;
        return unique;
    }

    tiling::WorkStore& store;
    double tolerance;
    bool layer_unique = true;
    std::size_t layers_ended = 0;
    tiling::VertexSample sample;
    std::size_t fid_cap;
    std::vector<std::int64_t> fids;
    std::size_t runs = 0;
    std::unique_ptr<tiling::OutFile> features;
    std::unique_ptr<tiling::OutFile> offsets;
    tiling::RecordWriter writer;
    SpoolMeta meta;
    std::string record;
};

FeatureSpool::FeatureSpool(tiling::WorkStore& store, double tolerance, std::size_t sample_cap, std::size_t fid_buffer)
    : m_impl(std::make_unique<Impl>(store, tolerance, sample_cap, fid_buffer))
{
}

FeatureSpool::~FeatureSpool() = default;

namespace {

// The largest feature so far: the first of the largest, in input order.
void note_largest(SpoolMeta& meta, std::uint64_t vertices, std::int64_t fid)
{
    if (vertices > meta.largest_vertices) {
        meta.largest_vertices = vertices;
        meta.largest_fid = fid;
    }
}

void count_spooled(SpoolMeta& meta, std::uint64_t vertices, std::int64_t fid)
{
    meta.vertices += vertices;
    note_largest(meta, vertices, fid);
    ++meta.spooled;
}

// One spooled feature's share of the read, the same for the spool and its parts: cleaned, its
// vertices sampled and counted in `meta`, its record encoded into `record`.
void spool_feature(std::uint64_t seq, std::int64_t fid, const Geometry& geometry, double tolerance,
                   std::vector<Problem>& problems, tiling::VertexSample& sample, SpoolMeta& meta, std::string& record)
{
    const detail::CleanFeature cf = detail::clean_feature(fid, geometry, seq, tolerance, problems);
    std::uint64_t n = 0;
    for (const detail::CleanRing& r : cf.rings) {
        for (const Coord& c : r.points) {
            sample.add(c.x, c.y);
        }
        n += r.points.size();
    }
    for (const auto& line : cf.lines) {
        for (const Coord& c : line) {
            sample.add(c.x, c.y);
        }
        n += line.size();
    }
    count_spooled(meta, n, fid);
    record.clear();
    tiling::ByteWriter w(record);
    tiling::put_clean_feature(w, cf, geometry.has_z);
}

} // namespace

void FeatureSpool::add(std::uint64_t seq, std::int64_t fid, const Geometry& geometry, std::vector<Problem>& problems)
{
    Impl& m = *m_impl;
    ++m.meta.records;
    m.note_fid(fid);
    spool_feature(seq, fid, geometry, m.tolerance, problems, m.sample, m.meta, m.record);
    m.write_record(m.record);
}

struct SpoolPart::Spill {
    Spill(tiling::WorkStore& s, std::string p)
        : prefix(std::move(p)), features(s.create(prefix + "features")), fids(s.create(prefix + "fids")), writer(*features)
    {
    }
    std::string prefix;
    std::unique_ptr<tiling::OutFile> features;
    std::unique_ptr<tiling::OutFile> fids;
    tiling::RecordWriter writer;
    bool sealed = false;
};

void FeatureSpool::append(SpoolPart&& part)
{
    Impl& m = *m_impl;
    if (part.m_spill) {
        SpoolPart::Spill& spill = *part.m_spill;
        if (!spill.sealed) {
            throw std::logic_error("FeatureSpool::append: the spilled part is not sealed");
        }
        // Its FIDs, then its records one by one, as add() and skip() would have taken them.
        {
            const std::unique_ptr<tiling::InFile> file = m.store.open(spill.prefix + "fids");
            tiling::BufferedReader fids(*file);
            std::int64_t fid = 0;
            std::uint64_t n = 0;
            for (std::size_t got; (got = fids.read(reinterpret_cast<char*>(&fid), sizeof fid)) == sizeof fid; ++n) {
                m.note_fid(fid);
            }
            if (n != part.m_meta.records) {
                throw tiling::work_error("damaged work file: " + spill.prefix + "fids holds " + std::to_string(n) +
                                         " FIDs, the part read " + std::to_string(part.m_meta.records));
            }
        }
        {
            const std::unique_ptr<tiling::InFile> file = m.store.open(spill.prefix + "features");
            tiling::RecordReader records(*file, std::size_t{4} << 20);
            std::uint64_t n = 0;
            for (; records.next(m.record); ++n) {
                m.write_record(m.record);
            }
            if (n != part.m_meta.spooled) {
                throw tiling::work_error("damaged work file: " + spill.prefix + "features holds " + std::to_string(n) +
                                         " records, the part spooled " + std::to_string(part.m_meta.spooled));
            }
        }
        m.store.remove(spill.prefix + "fids");
        m.store.remove(spill.prefix + "features");
    } else {
        for (const std::int64_t fid : part.m_fids) {
            m.note_fid(fid);
        }
        // The records' offsets in the features file, then their bytes: block by block, each
        // given to the file (in memory it becomes one of the file's chunks).
        const std::uint64_t base = m.features->bytes_written();
        std::string offsets;
        offsets.reserve(part.m_starts.size() * sizeof(std::uint64_t));
        for (const std::uint64_t start : part.m_starts) {
            const std::uint64_t offset = base + start;
            offsets.append(reinterpret_cast<const char*>(&offset), sizeof offset);
        }
        m.offsets->write(offsets);
        for (std::string& block : part.m_blocks) {
            m.features->write_block(std::move(block));
        }
    }
    m.meta.records += part.m_meta.records;
    m.meta.vertices += part.m_meta.vertices;
    note_largest(m.meta, part.m_meta.largest_vertices, part.m_meta.largest_fid); // the part's come later
    m.meta.spooled += part.m_meta.spooled;
    m.sample.append(std::move(part.m_sample));
    part = SpoolPart(part.m_tolerance, 16, part.m_block_bytes);
}


SpoolPart::SpoolPart(double tolerance, std::size_t sample_cap, std::size_t block_bytes)
    : m_tolerance(tolerance), m_sample(sample_cap), m_block_bytes(std::max<std::size_t>(block_bytes, 1))
{
}

SpoolPart::SpoolPart(double tolerance, std::size_t sample_cap, tiling::WorkStore& store, const std::string& prefix)
    : m_tolerance(tolerance), m_sample(sample_cap), m_block_bytes(1), m_spill(std::make_unique<Spill>(store, prefix))
{
}

SpoolPart::SpoolPart(SpoolPart&&) noexcept = default;
SpoolPart& SpoolPart::operator=(SpoolPart&&) noexcept = default;
SpoolPart::~SpoolPart() = default;

void SpoolPart::seal()
{
    if (m_spill && !m_spill->sealed) {
        m_spill->features->commit();
        m_spill->fids->commit();
        m_spill->sealed = true;
    }
}

void SpoolPart::add(std::uint64_t seq, std::int64_t fid, const Geometry& geometry, std::vector<Problem>& problems)
{
    ++m_meta.records;
    if (m_spill) {
        m_spill->fids->write(std::string_view(reinterpret_cast<const char*>(&fid), sizeof fid));
        spool_feature(seq, fid, geometry, m_tolerance, problems, m_sample, m_meta, m_record);
        m_spill->writer.write(m_record);
        return;
    }
    m_fids.push_back(fid);
    spool_feature(seq, fid, geometry, m_tolerance, problems, m_sample, m_meta, m_record);
    const auto n = static_cast<std::uint32_t>(m_record.size()); // RecordWriter::write's framing
    const std::size_t framed = sizeof n + m_record.size();
    if (m_blocks.empty() || m_blocks.back().size() + framed > m_blocks.back().capacity()) {
        m_blocks.emplace_back().reserve(std::max(m_block_bytes, framed));
    }
    m_blocks.back().append(reinterpret_cast<const char*>(&n), sizeof n);
    m_blocks.back() += m_record;
    m_starts.push_back(m_bytes);
    m_bytes += framed;
}

void SpoolPart::skip(std::int64_t fid)
{
    ++m_meta.records;
    if (m_spill) {
        m_spill->fids->write(std::string_view(reinterpret_cast<const char*>(&fid), sizeof fid));
        return;
    }
    m_fids.push_back(fid);
}

void FeatureSpool::skip(std::int64_t fid)
{
    ++m_impl->meta.records;
    m_impl->note_fid(fid);
}

bool FeatureSpool::end_layer()
{
    return m_impl->end_layer();
}

SpoolMeta FeatureSpool::finish()
{
    Impl& m = *m_impl;
    m.features->commit();
    m.offsets->commit();
    if (m.layers_ended == 0) {
        m.meta.fids_unique = m.end_layer();
    } else {
        m.meta.fids_unique = false; // several layers: their FIDs may repeat across them
    }
    m.meta.sample = m.sample.take();
    std::string bytes;
    tiling::ByteWriter w(bytes);
    m.meta.save(w, m.store.on_disk());
    m.store.put(files::spool_meta, bytes);
    return std::move(m.meta); // the sample is the caller's, not copied (up to 256 MiB)
}

SpooledFeatures::SpooledFeatures(const tiling::WorkStore& store, bool outline)
    : m_file(store.open(outline && spool_cut_to_outlines(store) ? files::outlines : files::features)), m_reader(*m_file),
      m_outline(outline)
{
}

SpooledFeatures::SpooledFeatures(const tiling::WorkStore& store, std::uint64_t begin, std::uint64_t end)
    : m_file(std::make_unique<tiling::FileRange>(store.open(files::features), begin, end)), m_reader(*m_file), m_outline(false)
{
}

bool spool_cut_to_outlines(const tiling::WorkStore& store)
{
    return !store.exists(files::features) && store.exists(files::outlines);
}

void cut_spool_to_outlines(tiling::WorkStore& store)
{
    if (spool_cut_to_outlines(store)) {
        return;
    }
    {
        const std::unique_ptr<tiling::InFile> in = store.open(files::features);
        tiling::RecordReader reader(*in);
        const std::unique_ptr<tiling::OutFile> out = store.create(files::outlines);
        tiling::RecordWriter writer(*out);
        std::string whole;
        std::string outline;
        while (reader.next(whole)) {
            tiling::ByteReader r(whole, "feature");
            outline.clear();
            tiling::ByteWriter w(outline);
            tiling::put_clean_outline(w, r);
            writer.write(outline);
        }
        out->commit();
    }
    store.remove(files::features);
    store.remove(files::offsets);
}

bool SpooledFeatures::next(detail::CleanFeature& f, bool& has_z)
{
    if (!m_reader.next(m_record)) {
        return false;
    }
    tiling::ByteReader r(m_record, "feature");
    f = tiling::get_clean_feature(r, has_z, m_outline);
    return true;
}

FeatureLookup::FeatureLookup(const tiling::WorkStore& store)
    : m_features(store.open(files::features)), m_offsets(store.open(files::offsets)), m_reader(*m_features)
{
    m_count = m_offsets->size() / sizeof(std::uint64_t);
}

detail::CleanFeature FeatureLookup::at(std::uint64_t rank, bool& has_z)
{
    std::uint64_t offset = 0;
    m_offsets->read_at(rank * sizeof offset, reinterpret_cast<char*>(&offset), sizeof offset);
    const std::string record = m_reader.at(offset);
    tiling::ByteReader r(record, "feature");
    return tiling::get_clean_feature(r, has_z);
}

detail::CleanFeature as_clean(const Feature& f)
{
    detail::CleanFeature cf;
    cf.id = f.id;
    cf.polygonal = f.geometry.is_polygonal();
    for (std::uint32_t p = 0; p < f.geometry.polygons.size(); ++p) {
        const auto& rings = f.geometry.polygons[p].rings;
        for (std::size_t k = 0; k < rings.size(); ++k) {
            detail::CleanRing ring;
            ring.points.assign(rings[k].begin(), rings[k].end() - 1);
            ring.polygon = p;
            ring.hole = k > 0;
            cf.rings.push_back(std::move(ring));
        }
    }
    cf.lines = f.geometry.lines;
    return cf;
}

} // namespace trisnap::stitch
