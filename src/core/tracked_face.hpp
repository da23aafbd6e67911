#pragma once
// The engine's triangulation face: CGAL's constrained face base, kept in the face info's bits,
// and a face that reports when CGAL creates it or changes its vertices or constraint flags, so
// the snapper re-examines exactly the faces an edit changed: no full rescans, and no rescans of
// a vertex of high degree (a frame corner, the hub of a fan) on every event near it.
//
// CGAL's data structure calls set_vertex/set_vertices/set_constraint on the face type it was
// given, so hiding them here sees every change, including faces it reuses in place (flips,
// insertion into a face). Changed faces are appended to the list installed with ChangedFaces
// on this thread (the engine is single-threaded per call; tiles run one snap() per thread),
// and nothing is recorded while none is installed (building, labelling).
//
// The constrained flags are three bits of the info (cdt::FaceInfo::constrained) instead of
// CGAL's Constrained_triangulation_face_base_2's three bools: the same interface CGAL calls
// (constructors, is_constrained, set_constraint(s), and reorient and the permutations, which
// move the flags with the edges). reorient and the permutations move flags without recording
// a change, as CGAL's base class did (its own calls are not the hidden ones).
#include <cstdint>
#include <vector>

namespace trisnap::cdt {

/// Where changed faces go while an instance is alive on this thread (scoped, not nestable).
class ChangedFaces {
public:
    explicit ChangedFaces(std::vector<void*>& sink) { s_sink = &sink; }
    ~ChangedFaces() { s_sink = nullptr; }
    ChangedFaces(const ChangedFaces&) = delete;
    ChangedFaces& operator=(const ChangedFaces&) = delete;
    static void note(void* face)
    {
        if (s_sink != nullptr) {
            s_sink->push_back(face);
        }
    }

private:
    static inline thread_local std::vector<void*>* s_sink = nullptr;
};

template <class Gt, class Fb>
class TrackedFace : public Fb {
public:
    using Vertex_handle = typename Fb::Vertex_handle;
    using Face_handle = typename Fb::Face_handle;

    template <class TDS2>
    struct Rebind_TDS {
        using Fb2 = typename Fb::template Rebind_TDS<TDS2>::Other;
        using Other = TrackedFace<Gt, Fb2>;
    };

    TrackedFace() { changed(); }
    TrackedFace(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2) : Fb(v0, v1, v2) { changed(); }
    TrackedFace(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2, Face_handle n0, Face_handle n1,
                Face_handle n2)
        : Fb(v0, v1, v2, n0, n1, n2)
    {
        changed();
    }
    TrackedFace(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2, Face_handle n0, Face_handle n1,
                Face_handle n2, bool c0, bool c1, bool c2)
        : Fb(v0, v1, v2, n0, n1, n2)
    {
        store_constraints(c0, c1, c2);
        changed();
    }
    TrackedFace(const TrackedFace& other) : Fb(other) { changed(); }
    TrackedFace& operator=(const TrackedFace&) = default;

    void set_vertex(int i, Vertex_handle v)
    {
        Fb::set_vertex(i, v);
        changed();
    }
    void set_vertices()
    {
        Fb::set_vertices();
        changed();
    }
    void set_vertices(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2)
    {
        Fb::set_vertices(v0, v1, v2);
        changed();
    }
    bool is_constrained(int i) const { return ((this->info().constrained >> i) & 1u) != 0; }
    void set_constraint(int i, bool b)
    {
        const std::uint32_t bit = 1u << i;
        this->info().constrained = b ? (this->info().constrained | bit) : (this->info().constrained & ~bit);
        changed();
    }
    void set_constraints(bool c0, bool c1, bool c2)
    {
        store_constraints(c0, c1, c2);
        changed();
    }
    void reorient()
    {
        Fb::reorient();
        store_constraints(is_constrained(1), is_constrained(0), is_constrained(2));
    }
    void ccw_permute()
    {
        Fb::ccw_permute();
        store_constraints(is_constrained(2), is_constrained(0), is_constrained(1));
    }
    void cw_permute()
    {
        Fb::cw_permute();
        store_constraints(is_constrained(1), is_constrained(2), is_constrained(0));
    }

private:
    void store_constraints(bool c0, bool c1, bool c2)
    {
        this->info().constrained = (c0 ? 1u : 0u) | (c1 ? 2u : 0u) | (c2 ? 4u : 0u);
    }
    void changed()
    {
        this->info().checked = false;
        ChangedFaces::note(this);
    }
};

} // namespace trisnap::cdt
