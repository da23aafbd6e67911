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

#include "app/allocator.hpp"
#include "app/command.hpp"
#include "io/dataset.hpp"
#include "io/sql_quote.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <system_error>
#include <thread>

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

// One feature's share of the read, the same on either reader: counted in `layer` and
// `smaller`, spooled (or skipped) in `spool`, its problems in `found`; its entry returned.
template <class Spool>
RecordEntry take_feature(InputFeature& feature, std::uint64_t seq, double tolerance, LayerRead& layer,
                         std::size_t& smaller, Spool& spool, std::vector<Problem>& found)
{
    found.clear();
    if (feature.problem) {
        found.push_back(*feature.problem);
    }
    RecordEntry e{feature.fid, RecordEntry::pass, false, static_cast<std::uint32_t>(feature.input_type)};
    if (feature.rejected) {
        e.verdict = RecordEntry::rejected;
        ++layer.rejected;
        spool.skip(feature.fid);
    } else if (feature.geometry) {
        e.verdict = RecordEntry::snap;
        layer.input_vertices += vertices_of(*feature.geometry);
        smaller += smaller_than_tolerance(*feature.geometry, tolerance) ? 1 : 0;
        ++layer.snapped;
        spool.add(seq, feature.fid, *feature.geometry, found);
    } else {
        spool.skip(feature.fid);
    }
    e.problem = !found.empty();
    ++layer.records;
    return e;
}

/// The files a second reader spills to (out of core); removed once appended, and at the start
/// of a read (an earlier attempt's).
const char* const k_read_part = "read-part-";

/// The features of a layer from input position `first` on (its second part), read on a thread
/// of its own from a dataset handle of its own while the caller reads the ones before: the same
/// work per feature (take_feature), kept until the caller has read up to `first` and appends it,
/// so that the work files are byte for byte the sequential read's. Its records.bin entries and
/// problems go to files of the store (k_read_part...: in memory for a store in memory); its
/// features' records are held in memory (stitch::SpoolPart's blocks, handed over without a copy)
/// or, with `spill` (out of core), written to the store too, so that it holds no more than its
/// sample and the files' buffers. Nothing but flat buffers crosses between the threads (handing features over
/// lost: REPORT.md "Reading beside the spool, again"). Where this reader starts is found by SQL
/// (start_at()); the caller takes them only when the feature it reads at `first` is the one this
/// reader began with (the same row), and reads on alone otherwise, as after any failure here
/// (join()).
class SecondReader {
public:
    SecondReader(const Plan& plan, std::uint64_t first, const ReadBuffers& buffers, tiling::WorkStore& store, bool spill,
                 const InterruptGuard& interrupt)
        : m_first(first), m_part(spill ? stitch::SpoolPart(plan.options.tolerance, buffers.sample_vertices, store, k_read_part)
                                       : stitch::SpoolPart(plan.options.tolerance, buffers.sample_vertices)),
          m_store(store), m_records_file(store.create(records_name())), m_problems_file(store.create(problems_name())),
          m_thread([this, &plan, &interrupt] { run(plan, interrupt); })
    {
    }
    ~SecondReader() { stop(); }
    SecondReader(const SecondReader&) = delete;
    SecondReader& operator=(const SecondReader&) = delete;

    std::uint64_t first() const { return m_first; }
    /// Features read so far (for the progress bar).
    std::uint64_t read() const { return m_read.load(std::memory_order_relaxed); }
    /// Waits for the reader; true when the caller's feature at `first` (`next`, null at the end
    /// of the layer) is where it began, so that its features are what the caller would read.
    bool join(const std::optional<InputFeature>& next)
    {
        m_thread.join();
        if (m_error) {
            try {
                std::rethrow_exception(m_error);
            } catch (const std::exception& e) {
                m_refusal = e.what();
            } catch (...) {
                m_refusal = "it failed";
            }
            return false;
        }
        if (next ? m_layer.records > 0 && m_first_fid == next->fid : m_layer.records == 0) {
            return true;
        }
        m_refusal = next ? "it began at FID " + (m_layer.records > 0 ? std::to_string(m_first_fid) : std::string("none")) +
                               ", the layer has FID " + std::to_string(next->fid) + " there"
                         : "it read features past the layer's end";
        return false;
    }
    /// Why join() said no.
    const std::string& refusal() const { return m_refusal; }
    std::uint64_t features() const { return m_layer.records; }
    /// Its features after the caller's, layer `k`'s; after a true join().
    void append_to(std::uint32_t k, LayerRead& layer, ReadTarget& to)
    {
        ReadSummary& s = to.summary;
        to.spool.append(std::move(m_part));
        append_files(k, to);
        s.records += m_layer.records;
        s.smaller += m_smaller;
        layer.records += m_layer.records;
        layer.rejected += m_layer.rejected;
        layer.snapped += m_layer.snapped;
        layer.input_vertices += m_layer.input_vertices;
    }

private:
    static std::string records_name() { return std::string(k_read_part) + "records"; }
    static std::string problems_name() { return std::string(k_read_part) + "problems"; }
    // The records.bin entries and the problems, read back from their files.
    void append_files(std::uint32_t k, ReadTarget& to)
    {
        {
            const std::unique_ptr<tiling::InFile> file = m_store.open(records_name());
            if (file->size() != m_layer.records * RecordEntry::k_bytes) {
                throw tiling::work_error("damaged work file: " + records_name() + " is not " + std::to_string(m_layer.records) + " entries");
            }
            std::string buffer(std::size_t{1} << 20, '\0');
            for (std::size_t got; (got = file->read(buffer.data(), buffer.size())) > 0;) {
                to.records.write(std::string_view(buffer.data(), got));
            }
        }
        {
            const std::unique_ptr<tiling::InFile> file = m_store.open(problems_name());
            tiling::RecordReader problems(*file);
            std::string record;
            std::uint64_t n = 0;
            for (; problems.next(record); ++n) {
                tiling::ByteReader r(record, "problem");
                Problem p = tiling::get_problem(r);
                p.layer = k;
                to.summary.problems.add(std::move(p));
            }
            if (n != m_problem_count) {
                throw tiling::work_error("damaged work file: " + problems_name() + " holds " + std::to_string(n) + " problems, the part found " +
                                         std::to_string(m_problem_count));
            }
        }
        m_store.remove(records_name());
        m_store.remove(problems_name());
    }
    void stop()
    {
        m_stop = true;
        if (m_thread.joinable()) {
            m_thread.join();
        }
    }
    void run(const Plan& plan, const InterruptGuard& interrupt)
    {
        advise_thread_heap(); // its heap in huge pages too (app/allocator.hpp: 0.49 s -> 0.31-0.33)
        try {
            const GDALDatasetUniquePtr dataset = open_input(plan.input_path, plan.open_options);
            OGRLayer* layer = dataset->GetLayerByName(plan.layer->GetName());
            if (layer == nullptr) {
                throw io_error(plan.input_path, plan.layer->GetName(), "the layer is gone");
            }
            const IgnoredAttributes ignored(*layer);
            LayerReader reader(*dataset, *layer, {layer});
            if (!start_at(*dataset, *layer)) {
                return; // the layer has no feature at m_first
            }
            std::vector<Problem> found;
            char entry[RecordEntry::k_bytes];
            tiling::RecordWriter problems(*m_problems_file); // framed
            std::string problem;
            while (!m_stop) {
                std::optional<InputFeature> feature = reader.next();
                if (!feature) {
                    break;
                }
                interrupt.check();
                if (m_layer.records == 0) {
                    m_first_fid = feature->fid;
                }
                const RecordEntry e = take_feature(*feature, m_first + m_layer.records, plan.tolerance, m_layer,
                                                   m_smaller, m_part, found);
                e.encode(entry);
                for (const Problem& p : found) {
                    problem.clear();
                    tiling::ByteWriter w(problem);
                    tiling::put_problem(w, p);
                    problems.write(problem);
                    ++m_problem_count;
                }
                m_records_file->write(std::string_view(entry, sizeof entry));
                m_read.store(m_layer.records, std::memory_order_relaxed);
            }
            if (!m_stop) { // committed here, on this thread, not while the caller waits
                m_part.seal();
                m_records_file->commit();
                m_problems_file->commit();
            }
        } catch (...) {
            m_error = std::current_exception(); // the caller reads these features itself
        }
    }

    // Positions the reader at input position m_first: its FID found by SQLite (a table's rows
    // come in rowid order, the GeoPackage FID; OFFSET skips rows without decoding them, where
    // GDAL's SetNextByIndex() would read every feature before), then a filter on the FID from
    // there (a seek in the rowid's B-tree). False when there is no row at m_first.
    bool start_at(GDALDataset& dataset, OGRLayer& layer) const
    {
        // TRISNAP_READ_SPLIT_SKEW (tests only) starts this many rows late: join() must refuse it.
        const char* skew = std::getenv("TRISNAP_READ_SPLIT_SKEW");
        const std::uint64_t offset = m_first + (skew != nullptr ? std::strtoull(skew, nullptr, 10) : 0);
        const std::string fid = layer.GetFIDColumn();
        if (fid.empty()) {
            throw std::runtime_error("no FID column");
        }
        const std::string sql = "SELECT " + sql_identifier(fid) + " AS trisnap_start FROM " + sql_identifier(layer.GetName()) +
                                " LIMIT 1 OFFSET " + std::to_string(offset);
        OGRLayer* rows = dataset.ExecuteSQL(sql.c_str(), nullptr, nullptr);
        if (rows == nullptr) {
            throw std::runtime_error("cannot find the FID at position " + std::to_string(offset));
        }
        const OGRFeatureUniquePtr row(rows->GetNextFeature());
        const bool found = row != nullptr;
        const std::int64_t start = !found ? 0 : row->GetFieldCount() > 0 ? row->GetFieldAsInteger64(0) : row->GetFID();
        dataset.ReleaseResultSet(rows);
        if (!found) {
            return false;
        }
        if (layer.SetAttributeFilter((sql_identifier(fid) + " >= " + std::to_string(start)).c_str()) != OGRERR_NONE) {
            throw std::runtime_error("cannot filter on the FID");
        }
        return true;
    }

    std::uint64_t m_first;
    stitch::SpoolPart m_part;
    tiling::WorkStore& m_store;
    std::unique_ptr<tiling::OutFile> m_records_file;  ///< records.bin's entries
    std::unique_ptr<tiling::OutFile> m_problems_file; ///< the problems, framed
    std::uint64_t m_problem_count = 0;                ///< problems written
    LayerRead m_layer; ///< records, rejected, snapped, input_vertices of its features
    std::size_t m_smaller = 0;
    std::int64_t m_first_fid = 0;
    std::exception_ptr m_error;
    std::string m_refusal;
    std::atomic<bool> m_stop{false};
    std::atomic<std::uint64_t> m_read{0};
    std::thread m_thread; ///< last: starts once the rest exists
};

// One layer, in input order; its problems are tagged with its index `k`. With `second`, the
// features from second->first() on come from it (when it agrees with this read).
void read_features(LayerReader& reader, std::uint32_t k, ReadTarget& to, SecondReader* second)
{
    ReadSummary& s = to.summary;
    LayerRead& layer = s.layers.emplace_back();
    std::vector<Problem> found; // one feature's
    char entry[RecordEntry::k_bytes];
    for (;;) {
        std::optional<InputFeature> feature = reader.next();
        if (second != nullptr && layer.records == second->first()) {
            const auto t0 = std::chrono::steady_clock::now();
            if (second->join(feature)) {
                const auto t1 = std::chrono::steady_clock::now();
                spdlog::info("read: features {} to {} of {} read on a second thread", second->first() + 1,
                             second->first() + second->features(), second->first() + second->features());
                second->append_to(k, layer, to);
                spdlog::debug("read: waited {:.3f} s for the second thread, took its features in {:.3f} s",
                              std::chrono::duration<double>(t1 - t0).count(),
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
                to.progress.update(static_cast<std::int64_t>(s.records));
                break;
            }
            spdlog::info("read: the second thread's features set aside ({}); read on one thread", second->refusal());
            second = nullptr; // read on alone
        }
        if (!feature) {
            break;
        }
        to.interrupt.check();
        const RecordEntry e = take_feature(*feature, s.records, to.tolerance, layer, s.smaller, to.spool, found);
        for (Problem& p : found) {
            p.layer = k;
            s.problems.add(std::move(p));
        }
        e.encode(entry);
        to.records.write(std::string_view(entry, sizeof entry));
        ++s.records;
        to.progress.update(static_cast<std::int64_t>(s.records + (second != nullptr ? second->read() : 0)));
    }
    layer.problems = s.problems.in_layer(k);
    s.rejected += layer.rejected;
    s.input_vertices += layer.input_vertices;
}

// Where a second reader takes over, or 0 for none: allowed by the budget (ReadBuffers), one
// layer of a GeoPackage (its features reachable by position through SQLite's OFFSET), no
// --where or --bbox, tiles, at least two threads, and enough features for a second dataset
// handle and thread to pay (TRISNAP_READ_SPLIT_MIN overrides the 20,000 for the tests).
std::uint64_t second_reader_start(const Plan& plan, const ReadBuffers& buffers)
{
    std::int64_t least = 20000;
    if (const char* v = std::getenv("TRISNAP_READ_SPLIT_MIN"); v != nullptr && *v != '\0') {
        least = std::max<std::int64_t>(1, std::atoll(v));
    }
    const int threads = plan.tiling.threads > 0 ? plan.tiling.threads : available_cores();
    // Not with --no-tiles: what the second thread's heap held stays with that heap (glibc keeps a
    // thread's arena for the next thread, and the tiles' threads take it up), where the one
    // triangulation cannot use it: Andorra x43 --no-tiles at 2 threads peaked at 647 MiB with it,
    // 608 without.
    if (!buffers.second_reader || threads < 2 || plan.tiling.plan.single || plan.layers.size() != 1 || plan.input_driver != "GPKG" ||
        plan.layer->GetAttrQueryString() != nullptr || plan.layer->GetSpatialFilter() != nullptr ||
        plan.feature_count < least || plan.feature_count < 2) {
        return 0;
    }
    // The second reader takes the last 40 %: it starts later (a dataset opened, the OFFSET
    // query) and reads a little slower; on Andorra x43 at 2 threads the plan phase took (medians
    // of 5, interleaved) 0.384 s with half each, 0.315 with 40 %, 0.326 with 35 %, 0.436 alone.
    return static_cast<std::uint64_t>(plan.feature_count - plan.feature_count * 2 / 5);
}

} // namespace

ReadSummary read_layer(Plan& plan, tiling::WorkStore& store, const ReadBuffers& buffers, Progress& progress,
                       const InterruptGuard& interrupt)
{
    ReadSummary s;
    s.problems = ProblemLog(store, k_read_problems, buffers.problem_bytes);
    s.problems.begin_phase(k_read_problems); // an earlier attempt's runs go
    store.remove_all(k_read_part);           // and a second reader's files
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
            std::unique_ptr<SecondReader> second;
            if (const std::uint64_t first = k == 0 ? second_reader_start(plan, buffers) : 0; first > 0) {
                try {
                    second = std::make_unique<SecondReader>(plan, first, buffers, store, store.on_disk(), interrupt);
                } catch (const std::system_error& e) { // no thread to be had: one reads it all
                    spdlog::info("read: no second thread ({}); read on one thread", e.what());
                }
            }
            read_features(reader, static_cast<std::uint32_t>(k), to, second.get());
            if (second) {
                second.reset();                 // its thread joined, its files closed
                store.remove_all(k_read_part); // what a part set aside (not taken) left
            }
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
