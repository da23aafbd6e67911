// Inserting and removing vertices at a cost that does not grow with a vertex's degree.
//
// Points on or near an exact circle are nearly co-circular, and in a Delaunay triangulation a
// vertex slightly inside such a circle (a merged vertex: the midpoint of a chord sits inside by
// the sagitta) is a neighbour of nearly every vertex on it. CGAL then pays for that degree on
// every edit: inserting the vertex flips an edge per neighbour, and removing it refills the hole
// with fill_hole_delaunay, which scans the whole hole for every triangle it makes (d^2 in-circle
// tests). A circle of 20,000 vertices at t = 0.01 reached degree 19,996 and took 10.6 s against
// 0.085 s at t = 1e-4; the review's 10^6 circle took 925 s (bench/results/REPORT.md).
//
// The snapper does not need the Delaunay property to be right: its searches walk every face that
// meets a disk or capsule, in any triangulation. Delaunay only keeps the faces it walks small on
// ordinary data. So the engine keeps CGAL's Delaunay edits where they are cheap and bounds them
// where they are not (Mesh::set_edit_bounds; defaults 1024 and 96):
//  - an inserted point restores the Delaunay property with CGAL's own flips in CGAL's order
//    (flip_around and the recursive propagating_flip, re-implemented with a budget); within
//    m_flip_budget flips (96, below CGAL's recursion depth of 100) the result is CGAL's
//    insertion exactly, beyond it the remaining edges stay as they are (legal, maybe not
//    Delaunay);
//  - a vertex of degree above m_hub_degree loses its incident constraints without CGAL's flips
//    (it is removed next, so those flips bought nothing) and is first reduced by flipping its
//    incident edges away, every other one per round around it, down to 64. Every
//    other one per round keeps the triangulation balanced: each neighbour gains at most two
//    edges per round, and a round takes up to half the edges away (on a convex ring all of
//    those), so no neighbour becomes the next hub;
//  - a removal uses CGAL's Delaunay hole fill only while no bound has left an edge as it was:
//    that fill puts the Delaunay triangles of the hole's vertices in, which lie inside the hole
//    only where the triangulation around it is Delaunay (with the bounds lowered to 6 and 2 it
//    made overlapping faces, caught by CGAL's validity check in a stress run of the tests).
//    From then on the removal is CGAL's plain ear fill, right in any triangulation; so is a hub
//    whose rounds could not get below the bound (reflex or collinear neighbours).
// On ordinary layers no bound is hit, so every edit is CGAL's own: the shared-layer runs (33,
// tiled and untiled, 1e-6 to 2 km) give byte-identical outputs and problems with and without.
// The largest degree a removal met there was 89 (BGT at 1 m): a hub bound of 64 took that run
// off CGAL's path, which the ear fills then changed; 1024 leaves a wide margin and still catches
// the circles' hubs (degrees in the thousands).
#include "core/mesh.hpp"

#include <stdexcept>
#include <string>

namespace trisnap::detail {

void Mesh::check_edit(const char* what) const
{
    if (m_check_edits && !m_tri.cdt::CtBase::is_valid()) {
        throw std::logic_error(std::string("trisnap: the triangulation is not valid after ") + what);
    }
}

#ifdef TRISNAP_PLAIN_CT
// The plain triangulation makes no flips: its own insertion is already bounded.
void Mesh::propagate_flip(cdt::Face_handle, int, int&) {}

cdt::Vertex_handle Mesh::insert_bounded(const cdt::Point& p, cdt::Triangulation::Locate_type lt, cdt::Face_handle loc,
                                        int li)
{
    return m_tri.insert(p, lt, loc, li);
}
#else
void Mesh::propagate_flip(cdt::Face_handle f, int i, int& budget)
{
    if (!m_tri.is_flipable(f, i)) {
        return;
    }
    if (budget == 0) { // an edge left as it is: the triangulation may no longer be Delaunay
        m_non_delaunay = true;
        return;
    }
    --budget;
    const cdt::Face_handle ni = f->neighbor(i);
    m_tri.flip(f, i);
    propagate_flip(f, i, budget);
    i = ni->index(f->vertex(i));
    propagate_flip(ni, i, budget);
}

cdt::Vertex_handle Mesh::insert_bounded(const cdt::Point& p, cdt::Triangulation::Locate_type lt, cdt::Face_handle loc,
                                        int li)
{
    const cdt::Vertex_handle v = m_tri.cdt::CtBase::insert(p, lt, loc, li);
    if (m_tri.dimension() < 2) {
        return v;
    }
    // CGAL's flip_around(v), with one budget for all its propagations. (The build's unbounded
    // twin without constraint flags is BuildFlips in mesh_build.cpp.)
    int budget = m_flip_budget;
    cdt::Face_handle f = v->face();
    const cdt::Face_handle start = f;
    cdt::Face_handle next;
    do {
        const int i = f->index(v);
        next = f->neighbor(cdt::Triangulation::ccw(i));
        propagate_flip(f, i, budget);
        f = next;
    } while (next != start);
    check_edit("an insertion");
    return v;
}
#endif

void Mesh::remove_incident_constraints_bounded(cdt::Vertex_handle h)
{
    if (m_tri.degree(h) > m_hub_degree) {
        m_tri.cdt::CtBase::remove_incident_constraints(h);
    } else {
        m_tri.remove_incident_constraints(h);
    }
}

void Mesh::remove_bounded(cdt::Vertex_handle h)
{
    std::size_t degree = m_tri.degree(h);
    if (degree > m_hub_degree) {
        shrink_hub(h);
        ++m_hub_removals;
        m_non_delaunay = true; // its flips, or the ear fill below if it could flip nothing
        degree = m_tri.degree(h);
    }
    m_removal_work += degree * degree;
    // CGAL's Delaunay removal fills the hole with the Delaunay triangles of its vertices, which
    // lie inside the hole only where the triangulation around it is Delaunay: once a bound left
    // an edge as it was, a removal uses CGAL's plain ear fill, right in any triangulation (the
    // Delaunay fill made overlapping faces there, caught by CGAL's is_valid with the bounds
    // lowered to 6 and 2 for a stress run of the tests).
    if (m_non_delaunay) {
        m_tri.cdt::CtBase::remove(h);
    } else {
        m_tri.remove(h);
    }
    check_edit("a removal");
}

// One round: the faces (h, w_k, w_k+1) around h, counter-clockwise, as they are at its start.
// Flipping the edge h-w_k (k even, never two neighbouring k) replaces the faces (h, w_k-1, w_k)
// and (h, w_k, w_k+1) by (h, w_k-1, w_k+1) and (w_k-1, w_k, w_k+1): it touches no face another
// flip of the round uses. The flip is legal when w_k-1 and w_k+1 see h and w_k on strictly
// opposite sides (exact orientations); an edge at h is never constrained here (its constraints
// were taken off first) and h, not being a frame corner, has no infinite neighbour.
void Mesh::shrink_hub(cdt::Vertex_handle h)
{
    std::vector<cdt::Face_handle>& ring = m_hub_faces;
    const std::size_t target = std::min<std::size_t>(64, m_hub_degree);
    for (;;) {
        ring.clear();
        auto fc = m_tri.incident_faces(h);
        const auto done = fc;
        do {
            if (m_tri.is_infinite(fc)) {
                return;
            }
            ring.push_back(fc);
        } while (++fc != done);
        const std::size_t d = ring.size();
        std::size_t degree = d;
        for (std::size_t k = 0; k + 1 < d && degree > target; k += 2) {
            const cdt::Face_handle f = ring[k];
            const int ih = f->index(h);
            const cdt::Vertex_handle w = f->vertex(cdt::Triangulation::ccw(ih));
            const cdt::Vertex_handle next = f->vertex(cdt::Triangulation::cw(ih));
            const int opposite = cdt::Triangulation::cw(ih); // the edge h-w
            const cdt::Face_handle g = f->neighbor(opposite);
            const cdt::Vertex_handle prev = g->vertex(m_tri.mirror_index(f, opposite));
            const CGAL::Orientation sh = CGAL::orientation(prev->point(), next->point(), h->point());
            const CGAL::Orientation sw = CGAL::orientation(prev->point(), next->point(), w->point());
            if (sh == CGAL::COLLINEAR || sw == CGAL::COLLINEAR || sh == sw || f->is_constrained(opposite)) {
                continue;
            }
            cdt::Face_handle ff = f;
            m_tri.flip(ff, opposite);
            m_non_delaunay = true;
            --degree;
        }
        if (degree == d || degree <= target) {
            return;
        }
    }
}

} // namespace trisnap::detail
