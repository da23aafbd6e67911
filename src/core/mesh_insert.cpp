// Inserting points and constraints so that CGAL never meets a crossing (see cdt_types.hpp).
//
// A segment a-b goes in as a stack of jobs. Each job walks the faces from a towards b with exact
// orientation tests and stops at the first obstacle:
//  - none: b is reached; CGAL inserts the constraint (one hole retriangulated) and the job's
//    owners are added to the edge;
//  - a vertex v lying exactly inside a-b: the job becomes a-v and v-b (same owners);
//  - a constrained edge r-l crossing a-b: their crossing is constructed exactly and rounded
//    (core/exact.hpp) to p. If p lies within two ulps of one of the four ends, the other segment
//    is routed through that end instead; otherwise p is inserted, r-l is replaced by r-p and p-l
//    (its owners), and the job by a-p and p-b. The new pieces are jobs like any other, so a piece
//    that the rounding made cross a third edge is split there too.
// In exact arithmetic every split would fall strictly inside a segment and the stack would empty
// after one split per crossing pair. Rounded, a split point lies within half an ulp of both
// segments, so a piece can only meet an edge that already passed within about an ulp of the
// crossing, and then usually within an ulp of the split point itself. Without the two-ulp rule
// two edges ending at nearly the same place crossed again one ulp further on after every
// split, creeping along forever (seen on Monaco); with it such a crossing reuses the split
// point. The same happened where two edges meet at a shallow angle: a rounded crossing lies up
// to about ulp / sin(angle) along the edges from the exact one, so an end within two ulps of
// the other edge (not of the crossing) takes the crossing too (Monaco's lines at 10 degrees). Cascades were never seen to last more than a few steps (tests/unit/core
// test_crossings), and a cap turns a run-away into an error instead of a hang. When the stack is empty the
// triangulation holds no two crossing constraints and every piece has kept its owners.
#include "core/exact.hpp"
#include "core/mesh.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace trisnap::detail {

cdt::Vertex_handle Mesh::insert_point(const cdt::Point& p, cdt::Face_handle hint)
{
    cdt::Triangulation::Locate_type lt;
    int li = 0;
    const cdt::Face_handle loc = m_tri.locate(p, lt, li, hint);
    if (lt == cdt::Triangulation::VERTEX) {
        return loc->vertex(li);
    }
    // A point exactly on a constrained edge: CGAL splits the edge and keeps both halves
    // constrained; the owners follow here, and the halves count as new edges (the snapper looks
    // for vertices near them: a split whose foot fell exactly on the edge left a vertex 0.016 t
    // from the new half unseen, found by fuzz_snap).
    const std::size_t first = m_arena.size();
    cdt::Vertex_handle er;
    cdt::Vertex_handle el;
    if (lt == cdt::Triangulation::EDGE && loc->is_constrained(li)) {
        er = loc->vertex(cdt::Triangulation::ccw(li));
        el = loc->vertex(cdt::Triangulation::cw(li));
        take_owners(id(er), id(el), m_arena);
    }
    const cdt::Vertex_handle v = insert_bounded(p, lt, loc, li);
    add_record(v, std::nan(""));
    m_vertices[id(v)].weight = 0;
    for (std::size_t k = first; k < m_arena.size(); ++k) {
        add_owner(id(er), id(v), m_arena[k]);
        add_owner(id(v), id(el), m_arena[k]);
    }
    if (er != cdt::Vertex_handle() && m_list_new_edges) {
        m_new_edges.emplace_back(id(er), id(v));
        m_new_edges.emplace_back(id(v), id(el));
    }
    m_arena.resize(first);
    return v;
}

void Mesh::push_job(cdt::Vertex_handle a, cdt::Vertex_handle b, std::uint32_t first, std::uint32_t count)
{
    if (a != b) { // a zero-length piece vanishes
        m_jobs.push_back(Job{a, b, first, count});
    }
}

void Mesh::insert_segment(cdt::Vertex_handle a, cdt::Vertex_handle b, std::span<const OwnerRef> owners)
{
    const auto first = static_cast<std::uint32_t>(m_arena.size());
    m_arena.insert(m_arena.end(), owners.begin(), owners.end());
    push_job(a, b, first, static_cast<std::uint32_t>(owners.size()));
    run_jobs();
    m_arena.clear();
}

void Mesh::run_jobs()
{
    constexpr std::size_t k_max_steps = 10'000'000;
    for (std::size_t step = 0; !m_jobs.empty(); ++step) {
        if (step == k_max_steps) {
            const cdt::Point& p = m_jobs.back().a->point();
            throw std::runtime_error("could not insert an edge without crossings near (" + std::to_string(p.x()) +
                                     ", " + std::to_string(p.y()) + ") after " + std::to_string(step) + " steps");
        }
        const Job job = m_jobs.back();
        m_jobs.pop_back();
        const Obstacle o = first_obstacle(job.a, job.b);
        if (o.kind == Obstacle::Kind::none) {
            constrain(job);
        } else if (o.kind == Obstacle::Kind::vertex) {
            push_job(o.v, job.b, job.first, job.count);
            push_job(job.a, o.v, job.first, job.count);
        } else {
            resolve_crossing(job, o.f, o.i);
        }
    }
}

void Mesh::constrain(const Job& job)
{
    // An edge of the triangulation already (most input edges, found so by first_obstacle) is
    // flagged on its two faces, as CGAL's insert_constraint would after walking a's neighbours
    // again to find it (includes_edge: ~3 % of a run on Natural Earth's countries).
    cdt::Face_handle f;
    int i = 0;
    if (m_tri.tds().is_edge(job.a, job.b, f, i)) {
        f->set_constraint(i, true);
        f->neighbor(i)->set_constraint(m_tri.mirror_index(f, i), true);
    } else {
        m_tri.insert_constraint(job.a, job.b);
    }
    if (m_list_new_edges) m_new_edges.emplace_back(id(job.a), id(job.b));
    for (std::uint32_t k = job.first; k < job.first + job.count; ++k) {
        add_owner(id(job.a), id(job.b), m_arena[k]);
    }
}

// The walk keeps the crossed edge (f, i) with its right end at ccw(i) and its left end at cw(i)
// as seen along a->b; the face beyond it tells by one orientation test where the segment exits.
Mesh::Obstacle Mesh::first_obstacle(cdt::Vertex_handle a, cdt::Vertex_handle b) const
{
    const cdt::Point& pa = a->point();
    const cdt::Point& pb = b->point();
    auto on_segment = [&](cdt::Vertex_handle v) {
        return CGAL::orientation(pa, pb, v->point()) == CGAL::COLLINEAR &&
               CGAL::collinear_are_ordered_along_line(pa, v->point(), pb);
    };
    // Most edges of an input ring join vertices that are neighbours already: found by handles
    // alone, before any predicate (no vertex lies on an edge of a triangulation, so none can be
    // an obstacle between neighbours).
    if (m_tri.tds().is_edge(a, b)) {
        return Obstacle{};
    }
    cdt::Face_handle f;
    int i = 0;
    auto fc = m_tri.incident_faces(a);
    const auto done = fc;
    do {
        if (m_tri.is_infinite(fc)) {
            continue;
        }
        const int ia = fc->index(a);
        const cdt::Vertex_handle r = fc->vertex(cdt::Triangulation::ccw(ia));
        const cdt::Vertex_handle l = fc->vertex(cdt::Triangulation::cw(ia));
        if (r == b || l == b) {
            return Obstacle{};
        }
        if (on_segment(r)) {
            return Obstacle{Obstacle::Kind::vertex, r, {}, 0};
        }
        if (on_segment(l)) {
            return Obstacle{Obstacle::Kind::vertex, l, {}, 0};
        }
        if (CGAL::orientation(pa, pb, r->point()) == CGAL::RIGHT_TURN &&
            CGAL::orientation(pa, pb, l->point()) == CGAL::LEFT_TURN) {
            f = fc;
            i = ia;
            break;
        }
    } while (++fc != done);
    if (f == cdt::Face_handle()) {
        throw std::logic_error("trisnap: no face around a vertex holds the direction of its edge");
    }
    for (;;) {
        if (f->is_constrained(i)) {
            return Obstacle{Obstacle::Kind::crossing, {}, f, i};
        }
        const cdt::Face_handle g = f->neighbor(i);
        const int j = m_tri.mirror_index(f, i);
        const cdt::Vertex_handle x = g->vertex(j);
        if (x == b) {
            return Obstacle{};
        }
        if (m_tri.is_infinite(x)) {
            throw std::logic_error("trisnap: a constraint walk left the triangulation");
        }
        const CGAL::Orientation side = CGAL::orientation(pa, pb, x->point());
        if (side == CGAL::COLLINEAR) {
            return Obstacle{Obstacle::Kind::vertex, x, {}, 0};
        }
        f = g;
        i = side == CGAL::LEFT_TURN ? cdt::Triangulation::ccw(j) : cdt::Triangulation::cw(j);
    }
}

// Replaces the constrained edge r-l by r-via and via-l (its owners follow); false when r-l is
// no longer an edge (a point inserted exactly on it already split it) or via is one of its ends.
bool Mesh::reroute(cdt::Vertex_handle r, cdt::Vertex_handle l, cdt::Vertex_handle via)
{
    cdt::Face_handle f;
    int i = 0;
    if (via == r || via == l || !m_tri.is_edge(r, l, f, i) || !f->is_constrained(i)) {
        return false;
    }
    const auto first = static_cast<std::uint32_t>(m_arena.size());
    take_owners(id(r), id(l), m_arena);
    const auto count = static_cast<std::uint32_t>(m_arena.size() - first);
    m_tri.remove_constrained_edge(f, i);
    push_job(via, l, first, count);
    push_job(r, via, first, count);
    return true;
}

void Mesh::resolve_crossing(const Job& job, cdt::Face_handle f, int i)
{
    const cdt::Vertex_handle r = f->vertex(cdt::Triangulation::ccw(i));
    const cdt::Vertex_handle l = f->vertex(cdt::Triangulation::cw(i));
    const cdt::Point p = rounded_crossing(job.a->point(), job.b->point(), r->point(), l->point());
    // The nearest of the four ends within two ulps of the crossing or of the other edge takes the
    // crossing's place (see exact.hpp).
    cdt::Vertex_handle via;
    double best = 0;
    const cdt::Vertex_handle ends[4] = {job.a, job.b, r, l};
    for (int k = 0; k < 4; ++k) {
        const cdt::Vertex_handle end = ends[k];
        const cdt::Point& o0 = ends[k < 2 ? 2 : 0]->point(); // the other edge
        const cdt::Point& o1 = ends[k < 2 ? 3 : 1]->point();
        const bool close = within_ulps(end->point(), p, k_crossing_snap_ulps) ||
                           within_ulps_of_segment(end->point(), o0, o1, k_crossing_snap_ulps);
        const double d2 = CGAL::squared_distance(end->point(), p);
        if (close && (via == cdt::Vertex_handle() || d2 < best)) {
            via = end;
            best = d2;
        }
    }
    if (via == cdt::Vertex_handle()) {
        const std::size_t slots = m_vertices.size();
        via = insert_point(p, f);
        if (m_vertices.size() > slots) {
            m_created.push_back(id(via));
        }
    }
    // A crossing that rounds to an end of a-b reroutes only r-l, through that end; the job is
    // then tried again whole (r-l now passes through its end, so the walk finds the next
    // obstacle). The pieces of r-l are pushed last, so they go in first.
    if (via == job.a || via == job.b) {
        push_job(job.a, job.b, job.first, job.count);
    } else {
        push_job(via, job.b, job.first, job.count);
        push_job(job.a, via, job.first, job.count);
    }
    reroute(r, l, via);
}

} // namespace trisnap::detail
