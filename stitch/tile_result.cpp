#include "stitch/tile_result.hpp"

#include "tiling/records.hpp"

#include <bit>
#include <tuple>

namespace trisnap::stitch {
namespace {

auto seam_key(const SeamEdge& e)
{
    return std::make_tuple(e.rank, e.edge.a.x, e.edge.a.y, e.edge.b.x, e.edge.b.y,
                           std::bit_cast<std::uint64_t>(e.edge.a.z), std::bit_cast<std::uint64_t>(e.edge.b.z));
}

void put_stats(tiling::ByteWriter& w, const SnapStats& s)
{
    for (std::size_t v : {s.input_features, s.input_vertices, s.triangulation_vertices, s.output_vertices, s.intersections,
                          s.merges, s.splits, s.rounds, s.faces_visited, s.fixpoint_misses, s.collapsed_features}) {
        w.put<std::uint64_t>(v);
    }
    for (double v : {s.max_displacement, s.seconds_triangulate, s.seconds_snap, s.seconds_label, s.seconds_extract}) {
        w.put(v);
    }
}

SnapStats get_stats(tiling::ByteReader& r)
{
    SnapStats s;
    for (std::size_t* v : {&s.input_features, &s.input_vertices, &s.triangulation_vertices, &s.output_vertices,
                           &s.intersections, &s.merges, &s.splits, &s.rounds, &s.faces_visited, &s.fixpoint_misses,
                           &s.collapsed_features}) {
        *v = r.get<std::uint64_t>();
    }
    for (double* v : {&s.max_displacement, &s.seconds_triangulate, &s.seconds_snap, &s.seconds_label, &s.seconds_extract}) {
        *v = r.get<double>();
    }
    return s;
}

} // namespace

void put_piece(tiling::ByteWriter& w, const Piece& p)
{
    w.put<std::uint64_t>(p.rank);
    w.put(p.displacement);
    const bool finished = !p.whole && !p.geometry.polygons.empty();
    w.put<std::uint8_t>(static_cast<std::uint8_t>((p.whole ? 1 : 0) | (p.has_z ? 2 : 0) | (finished ? 4 : 0)));
    if (p.whole) {
        tiling::put_geometry(w, p.geometry);
    } else {
        tiling::put_edges(w, p.edges, p.has_z);
        if (finished) {
            tiling::put_geometry(w, p.geometry);
        }
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(p.problems.size()));
    for (const Problem& q : p.problems) {
        tiling::put_problem(w, q);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(p.shared.size()));
    for (const SharedBoundary& s : p.shared) {
        w.put<std::int64_t>(s.other);
        w.put<std::uint64_t>(s.other_position);
        w.put<std::uint8_t>(static_cast<std::uint8_t>((s.before ? 1 : 0) | (s.after ? 2 : 0)));
        w.put(s.x);
        w.put(s.y);
        w.put(s.length);
    }
}

Piece get_piece(tiling::ByteReader& r)
{
    Piece p;
    p.rank = r.get<std::uint64_t>();
    p.displacement = r.get<double>();
    const auto flags = r.get<std::uint8_t>();
    p.whole = (flags & 1) != 0;
    p.has_z = (flags & 2) != 0;
    if (p.whole) {
        p.geometry = tiling::get_geometry(r);
    } else {
        p.edges = tiling::get_edges(r);
        if ((flags & 4) != 0) {
            p.geometry = tiling::get_geometry(r);
        }
    }
    p.problems.resize(r.get_count(24));
    for (Problem& q : p.problems) {
        q = tiling::get_problem(r);
    }
    p.shared.resize(r.get_count(41));
    for (SharedBoundary& s : p.shared) {
        s.other = r.get<std::int64_t>();
        s.other_position = r.get<std::uint64_t>();
        const auto flags = r.get<std::uint8_t>();
        s.before = (flags & 1) != 0;
        s.after = (flags & 2) != 0;
        s.x = r.get<double>();
        s.y = r.get<double>();
        s.length = r.get<double>();
    }
    return p;
}

void put_seam_edge(tiling::ByteWriter& w, const SeamEdge& e)
{
    w.put<std::uint64_t>(e.rank);
    tiling::put_edges(w, {e.edge}, true);
    w.put<std::uint8_t>(e.owned ? 1 : 0);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(e.near.size()));
    for (std::uint32_t leaf : e.near) {
        w.put(leaf);
    }
}

SeamEdge get_seam_edge(tiling::ByteReader& r)
{
    SeamEdge e;
    e.rank = r.get<std::uint64_t>();
    const std::vector<DirectedEdge> edges = tiling::get_edges(r);
    if (edges.size() != 1) {
        throw tiling::record_error("damaged work file: a seam record holds no edge");
    }
    e.edge = edges[0];
    e.owned = r.get<std::uint8_t>() != 0;
    e.near.resize(r.get_count(sizeof(std::uint32_t)));
    for (std::uint32_t& leaf : e.near) {
        leaf = r.get<std::uint32_t>();
    }
    return e;
}

void put_tile_report(tiling::ByteWriter& w, const TileReport& t)
{
    w.put<std::uint64_t>(t.id);
    w.put<std::uint64_t>(t.leaves);
    for (double v : {t.core.xmin, t.core.ymin, t.core.xmax, t.core.ymax, t.halo}) {
        w.put(v);
    }
    w.put<std::int32_t>(t.growths);
    w.put<std::uint8_t>(t.cascade_unbounded ? 1 : 0);
    w.put(t.cascade_x);
    w.put(t.cascade_y);
    w.put(t.cascade_rank);
    for (std::size_t v : {t.features, t.input_vertices, t.output_edges_owned, t.problems, t.runs}) {
        w.put<std::uint64_t>(v);
    }
    w.put(t.seconds);
    put_stats(w, t.stats);
    w.put<std::uint8_t>(t.failed ? 1 : 0);
    w.put_string(t.failure);
}

TileReport get_tile_report(tiling::ByteReader& r)
{
    TileReport t;
    t.id = r.get<std::uint64_t>();
    t.leaves = r.get<std::uint64_t>();
    for (double* v : {&t.core.xmin, &t.core.ymin, &t.core.xmax, &t.core.ymax, &t.halo}) {
        *v = r.get<double>();
    }
    t.growths = r.get<std::int32_t>();
    t.cascade_unbounded = r.get<std::uint8_t>() != 0;
    t.cascade_x = r.get<double>();
    t.cascade_y = r.get<double>();
    t.cascade_rank = r.get<std::uint64_t>();
    for (std::size_t* v : {&t.features, &t.input_vertices, &t.output_edges_owned, &t.problems, &t.runs}) {
        *v = r.get<std::uint64_t>();
    }
    t.seconds = r.get<double>();
    t.stats = get_stats(r);
    t.failed = r.get<std::uint8_t>() != 0;
    t.failure = r.get_string();
    return t;
}

bool seam_less(const SeamEdge& a, const SeamEdge& b) { return seam_key(a) < seam_key(b); }

bool seam_equal(const SeamEdge& a, const SeamEdge& b) { return seam_key(a) == seam_key(b); }

std::string encode_notes(const std::vector<std::pair<std::uint64_t, Problem>>& notes)
{
    std::string bytes;
    tiling::ByteWriter w(bytes);
    w.put<std::uint64_t>(notes.size());
    for (const auto& [rank, p] : notes) {
        w.put(rank);
        tiling::put_problem(w, p);
    }
    return bytes;
}

std::vector<std::pair<std::uint64_t, Problem>> decode_notes(const std::string& bytes)
{
    tiling::ByteReader r(bytes, "notes");
    std::vector<std::pair<std::uint64_t, Problem>> notes(r.get<std::uint64_t>());
    for (auto& [rank, p] : notes) {
        rank = r.get<std::uint64_t>();
        p = tiling::get_problem(r);
    }
    return notes;
}

} // namespace trisnap::stitch
