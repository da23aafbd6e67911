#include "stitch/output.hpp"

#include "core/assemble.hpp"
#include "core/outcome.hpp"
#include "core/shared_boundaries.hpp"
#include "tiling/tile_input.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <map>
#include <queue>
#include <set>
#include <tuple>

namespace trisnap::stitch {
namespace {

constexpr std::size_t k_reader_buffer = 1 << 16;

std::uint64_t rank_of(const std::string& record)
{
    std::uint64_t rank = 0;
    if (record.size() < sizeof rank) {
        throw tiling::record_error("damaged work file: a result record is too short");
    }
    std::memcpy(&rank, record.data(), sizeof rank);
    return rank;
}

// Piece records of several files (each in rank order), merged in rank order (ties by file).
class PieceStream {
public:
    struct Input {
        std::string name;
        bool skip_report = false; ///< a result file: its first record is the tile's report
    };
    PieceStream(const tiling::WorkStore& store, const std::vector<Input>& inputs)
    {
        for (const Input& in : inputs) {
            m_files.push_back(store.open(in.name));
            m_readers.push_back(std::make_unique<tiling::RecordReader>(*m_files.back(), k_reader_buffer));
            std::string record;
            if (in.skip_report) {
                m_readers.back()->next(record);
            }
            pull(m_readers.size() - 1);
        }
    }
    bool peek(std::uint64_t& rank) const
    {
        if (m_heap.empty()) {
            return false;
        }
        rank = std::get<0>(m_heap.top());
        return true;
    }
    /// The next record (the smallest rank, then the first file).
    std::string pop()
    {
        const std::size_t k = std::get<1>(m_heap.top());
        m_heap.pop();
        std::string record = std::move(m_heads[k]);
        pull(k);
        return record;
    }

private:
    void pull(std::size_t k)
    {
        m_heads.resize(m_readers.size());
        if (m_readers[k]->next(m_heads[k])) {
            m_heap.emplace(rank_of(m_heads[k]), k);
        }
    }

    std::vector<std::unique_ptr<tiling::InFile>> m_files;
    std::vector<std::unique_ptr<tiling::RecordReader>> m_readers;
    std::vector<std::string> m_heads;
    using Head = std::tuple<std::uint64_t, std::size_t>;
    std::priority_queue<Head, std::vector<Head>, std::greater<>> m_heap;
};

// Merges inputs into files of at most k_merge_fan_in inputs each until one stream can take them.
std::vector<PieceStream::Input> merge_rounds(tiling::WorkStore& store, std::vector<PieceStream::Input> inputs)
{
    for (int round = 0; inputs.size() > k_merge_fan_in; ++round) {
        std::vector<PieceStream::Input> next;
        for (std::size_t first = 0; first < inputs.size(); first += k_merge_fan_in) {
            const std::vector<PieceStream::Input> batch(inputs.begin() + static_cast<std::ptrdiff_t>(first),
                                                        inputs.begin() + static_cast<std::ptrdiff_t>(std::min(inputs.size(), first + k_merge_fan_in)));
            const std::string name = "merge-" + std::to_string(round) + "-" + std::to_string(next.size());
            PieceStream stream(store, batch);
            const std::unique_ptr<tiling::OutFile> out = store.create(name);
            tiling::RecordWriter writer(*out);
            std::uint64_t rank = 0;
            while (stream.peek(rank)) {
                writer.write(stream.pop());
            }
            out->commit();
            next.push_back({name, false});
        }
        inputs = std::move(next);
    }
    return inputs;
}

} // namespace

struct OutputMerger::Impl {
    Impl(tiling::WorkStore& s, const SpoolMeta& m, const SnapOptions& o) : store(s), meta(m), options(o), spooled(s, true) {}
    void read_reports(const std::vector<std::size_t>& live);
    /// The feature's output from its pieces (a whole piece's geometry is moved out of it).
    Geometry build(const detail::CleanFeature& cf, bool has_z, std::vector<Piece>& pieces);
    void tile_problems(const detail::CleanFeature& cf, const std::vector<Piece>& pieces, std::vector<Problem>& out) const;
    void lost_boundaries(const detail::CleanFeature& cf, std::uint64_t here, const Geometry& g,
                         std::vector<Piece>& pieces, std::vector<Problem>& out);

    tiling::WorkStore& store;
    const SpoolMeta& meta;
    const SnapOptions& options;
    SpooledFeatures spooled; ///< outlines: build, tile_problems and outcome_problems need no more
    std::unique_ptr<PieceStream> stream;
    std::vector<TileReport> tiles;
    OutputCounts counts;
    std::vector<std::pair<std::uint64_t, Problem>> seam_problems; ///< sorted by rank
    std::size_t next_seam = 0;
    std::uint64_t rank = 0;
    /// (later rank, earlier rank) of pairs that may have lost their boundary, the earlier one
    /// written: what lost_boundaries() needs from the earlier one's turn.
    std::set<std::pair<std::uint64_t, std::uint64_t>> earlier_written;
};

void OutputMerger::Impl::read_reports(const std::vector<std::size_t>& live)
{
    std::string record;
    for (std::size_t g : live) {
        const std::unique_ptr<tiling::InFile> file = store.open(files::result(g));
        tiling::RecordReader reader(*file, 4096);
        if (!reader.next(record)) {
            throw tiling::record_error("damaged work file: " + files::result(g) + " has no tile report");
        }
        tiling::ByteReader r(record, "tile report");
        tiles.push_back(get_tile_report(r));
        counts.stats += tiles.back().stats;
    }
}

Geometry OutputMerger::Impl::build(const detail::CleanFeature& cf, bool has_z, std::vector<Piece>& pieces)
{
    // A piece with no geometry (only a move, problems or shared-boundary evidence) adds no edge.
    const auto carries = [](const Piece& p) { return p.whole || !p.edges.empty() || !p.geometry.polygons.empty(); };
    if (std::count_if(pieces.begin(), pieces.end(), carries) == 1) {
        Piece& only = *std::find_if(pieces.begin(), pieces.end(), carries);
        if (only.whole) {
            ++counts.copied;
            Geometry g = std::move(only.geometry);
            g.has_z = has_z;
            return g;
        }
    }
    // The edges in one vector of the size they need (a feature across every tile, as Natural
    // Earth's land, has ~0.4 M of 48 bytes), each piece's freed once taken: fresh memory costs
    // page faults, ~2 ms a MB on the team's VM (REPORT.md, "The stitch's memory").
    const auto is_edges = [&](const Piece& p) { return p.whole || !cf.polygonal; };
    std::size_t total = 0;
    for (const Piece& p : pieces) {
        total += p.edges.size();
        if (is_edges(p)) {
            for (const Polygon& poly : p.geometry.polygons) {
                for (const Path& r : poly.rings) {
                    total += r.empty() ? 0 : r.size() - 1;
                }
            }
            for (const Path& l : p.geometry.lines) {
                total += l.empty() ? 0 : l.size() - 1;
            }
        }
    }
    std::vector<DirectedEdge> edges;
    edges.reserve(total);
    std::vector<Polygon> finished;
    for (Piece& p : pieces) {
        edges.insert(edges.end(), p.edges.begin(), p.edges.end());
        std::vector<DirectedEdge>().swap(p.edges);
        if (!is_edges(p)) {
            std::move(p.geometry.polygons.begin(), p.geometry.polygons.end(), std::back_inserter(finished));
            continue;
        }
        for (const Polygon& poly : p.geometry.polygons) {
            append_ring_edges(poly, edges);
        }
        for (const Path& l : p.geometry.lines) {
            for (std::size_t i = 0; i + 1 < l.size(); ++i) {
                edges.push_back(DirectedEdge{l[i], l[i + 1]});
            }
        }
        p.geometry = Geometry{};
    }
    if (edges.empty() && finished.empty()) {
        return Geometry{Geometry::Type::Empty, {}, {}, has_z};
    }
    ++counts.assembled;
    if (cf.polygonal) {
        return assemble_polygons(std::move(edges), has_z, std::move(finished));
    }
    std::vector<Coord> starts;
    for (const auto& line : cf.lines) {
        starts.push_back(round_to_grid(line.front(), options.grid));
    }
    return assemble_lines(std::move(edges), starts, has_z);
}

// One problem per code and feature, at the smallest place any tile reported it; a crossing
// (105) is placed where the engine places it: the feature's first point.
void OutputMerger::Impl::tile_problems(const detail::CleanFeature& cf, const std::vector<Piece>& pieces,
                                       std::vector<Problem>& out) const
{
    std::map<int, Problem> by_code;
    for (const Piece& piece : pieces) {
        for (const Problem& p : piece.problems) {
            auto [it, added] = by_code.try_emplace(static_cast<int>(p.code), p);
            if (!added && std::tie(p.x, p.y) < std::tie(it->second.x, it->second.y)) {
                it->second = p;
            }
        }
    }
    for (auto& [code, p] : by_code) {
        p.feature_id = cf.id;
        if (p.code == ProblemCode::self_intersection && !cf.rings.empty()) {
            p.x = cf.rings[0].points[0].x;
            p.y = cf.rings[0].points[0].y;
        }
        out.push_back(std::move(p));
    }
}

// 210: the tiles' evidence of the feature's shared boundaries, merged pair by pair, judged by
// the engine's rule (core/shared_boundaries.hpp) on the later feature of a pair: the earlier one
// left, at its turn, whether it was written, for the pairs that may be lost (few). Other features
// are named by their engine id: the FID, or the input position when FIDs repeat across layers.
void OutputMerger::Impl::lost_boundaries(const detail::CleanFeature& cf, std::uint64_t here, const Geometry& g,
                                         std::vector<Piece>& pieces, std::vector<Problem>& out)
{
    std::vector<SharedBoundary> shared;
    for (Piece& p : pieces) {
        shared.insert(shared.end(), p.shared.begin(), p.shared.end());
        p.shared.clear();
    }
    detail::merge_shared_boundaries(shared);
    for (const SharedBoundary& s : shared) {
        if (s.other_position > here && !g.empty() && detail::lost_candidate(s, options.tolerance)) {
            earlier_written.emplace(s.other_position, here);
        }
    }
    const bool fids = meta.fids_unique;
    detail::report_lost_boundaries(
        cf.id, here, !g.empty(), options.tolerance, shared,
        [&](const SharedBoundary& s) { return earlier_written.count({here, s.other_position}) > 0; },
        [fids](std::int64_t other) {
            return fids ? "FID " + std::to_string(other) : "the feature at input position " + std::to_string(other);
        },
        out);
}

OutputMerger::OutputMerger(tiling::WorkStore& store, const TileLayout& layout, const Groups& groups, const SpoolMeta& meta,
                           const SnapOptions& options)
    : m_impl(std::make_unique<Impl>(store, meta, options))
{
    const std::vector<std::size_t> live = groups.live(layout);
    m_impl->read_reports(live);
    std::vector<PieceStream::Input> inputs;
    for (std::size_t g : live) {
        inputs.push_back({files::result(g), true});
    }
    m_impl->stream = std::make_unique<PieceStream>(store, merge_rounds(store, std::move(inputs)));
    SnapStats& s = m_impl->counts.stats;
    s.input_features = meta.spooled;
    s.input_vertices = meta.vertices;
    s.collapsed_features = 0;
    s.max_displacement = 0;
    s.output_vertices = 0;
}

OutputMerger::~OutputMerger() = default;

void OutputMerger::set_notes(std::vector<std::pair<std::uint64_t, Problem>> notes)
{
    std::stable_sort(notes.begin(), notes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    m_impl->seam_problems = std::move(notes);
}

bool OutputMerger::next(OutputItem& item)
{
    Impl& m = *m_impl;
    detail::CleanFeature cf;
    bool has_z = false;
    if (!m.spooled.next(cf, has_z)) {
        return false;
    }
    const std::uint64_t rank = m.rank++;
    std::vector<Piece> pieces;
    std::uint64_t head = 0;
    while (m.stream->peek(head) && head <= rank) {
        const std::string record = m.stream->pop();
        if (head < rank) {
            throw tiling::record_error("damaged work file: a tile result names a feature out of order");
        }
        tiling::ByteReader r(record, "piece");
        pieces.push_back(get_piece(r));
    }
    item = OutputItem{};
    item.seq = cf.index;
    item.output.id = cf.id;
    item.output.geometry.has_z = has_z;
    const bool failed = std::any_of(pieces.begin(), pieces.end(), [](const Piece& p) {
        return std::any_of(p.problems.begin(), p.problems.end(), [](const Problem& q) { return q.code == ProblemCode::tile_failed; });
    });
    if (failed) {
        // A tile it met failed (--on-error skip): the edges that tile owned are missing, so the
        // feature is not written at all; 303 says why (with what else the tiles found).
        m.tile_problems(cf, pieces, item.problems);
        ++m.counts.failed;
    } else if (!cf.rejected) {
        item.output.geometry = m.build(cf, has_z, pieces);
        for (const Piece& p : pieces) {
            item.output.max_displacement = std::max(item.output.max_displacement, p.displacement);
        }
        m.tile_problems(cf, pieces, item.problems);
        if (detail::outcome_problems(detail::outline_of(cf), item.output.geometry, item.output.max_displacement, m.options, item.problems)) {
            ++m.counts.stats.collapsed_features;
        }
        m.lost_boundaries(cf, rank, item.output.geometry, pieces, item.problems);
    }
    m.earlier_written.erase(m.earlier_written.lower_bound({rank, 0}), m.earlier_written.lower_bound({rank + 1, 0}));
    for (; m.next_seam < m.seam_problems.size() && m.seam_problems[m.next_seam].first == rank; ++m.next_seam) {
        Problem p = m.seam_problems[m.next_seam].second;
        p.feature_id = cf.id;
        item.problems.push_back(std::move(p));
    }
    SnapStats& s = m.counts.stats;
    s.max_displacement = std::max(s.max_displacement, item.output.max_displacement);
    s.output_vertices += tiling::engine_vertices(item.output.geometry);
    std::stable_sort(item.problems.begin(), item.problems.end(),
                     [](const Problem& a, const Problem& b) { return a.code < b.code; });
    return true;
}

const std::vector<TileReport>& OutputMerger::tiles() const { return m_impl->tiles; }

const OutputCounts& OutputMerger::counts() const { return m_impl->counts; }

} // namespace trisnap::stitch
