// Pairs of polygons: overlaps that snapping created and shared boundaries it broke. Candidate
// pairs come from a GEOS STRtree over feature envelopes; one DE-9IM relate per pair decides,
// and the (costlier) overlay that measures an area or a length runs only when relate says the
// interiors meet or the boundaries share a line. Shared boundary length is first summed over
// segments the two features have in common exactly (what a coverage has), which spares the
// overlay for almost every neighbour pair.
#include "checker_detail.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace trisnap::checker_detail {
namespace {

using IdPair = std::pair<std::int64_t, std::int64_t>;

struct PairState {
    bool overlap = false; ///< interiors meet with area > 1e-9 t^2
    bool shared = false;  ///< boundaries share a line (input: longer than 2t)
    double x = 0.0, y = 0.0; ///< a point of the overlap or of the shared boundary
};

struct Measure {
    double value, x, y;
};

/// What the pair's DE-9IM says, as far as we need it. `inside` is the geometry that lies
/// properly inside the other one, when that is so: its area is then the overlap, no overlay.
struct Relation {
    bool failed = false;
    bool interiors_meet = false;
    bool boundaries_share_line = false;
    const GEOSGeometry* inside = nullptr;
};

std::uint64_t pair_key(std::size_t i, std::size_t j) {
    return (static_cast<std::uint64_t>(std::min(i, j)) << 32) | std::max(i, j);
}

/// Length of the segments that features i < j both have (exactly), keyed by pair_key.
std::unordered_map<std::uint64_t, Measure> common_segments(const Side& side) {
    std::vector<Segment> segs = side.segments;
    for (Segment& s : segs)
        if (std::tie(s.bx, s.by) < std::tie(s.ax, s.ay)) {
            std::swap(s.ax, s.bx);
            std::swap(s.ay, s.by);
        }
    auto coords = [](const Segment& s) { return std::tie(s.ax, s.ay, s.bx, s.by); };
    std::sort(segs.begin(), segs.end(), [&](const Segment& a, const Segment& b) {
        return std::tie(a.ax, a.ay, a.bx, a.by, a.feature) < std::tie(b.ax, b.ay, b.bx, b.by, b.feature);
    });
    std::unordered_map<std::uint64_t, Measure> lengths;
    for (std::size_t k = 0; k + 1 < segs.size(); ++k) {
        for (std::size_t m = k + 1; m < segs.size() && coords(segs[m]) == coords(segs[k]); ++m) {
            if (segs[m].feature == segs[k].feature)
                continue;
            const Segment& s = segs[k];
            Measure& l = lengths.try_emplace(pair_key(s.feature, segs[m].feature),
                                             Measure{0.0, 0.5 * (s.ax + s.bx), 0.5 * (s.ay + s.by)})
                             .first->second;
            l.value += std::hypot(s.bx - s.ax, s.by - s.ay);
        }
    }
    return lengths;
}

class PairScan {
public:
    /// The input scan measures shared lengths; the output scan gets the input's states and
    /// skips measuring overlaps the input already had (they cannot be new).
    PairScan(GeosContext& ctx, const Side& side, double t, bool measure_shared,
             const std::map<IdPair, PairState>* before = nullptr)
        : m_ctx(ctx), m_side(side), m_t(t), m_measure_shared(measure_shared), m_before(before),
          m_common(measure_shared ? common_segments(side)
                                  : std::unordered_map<std::uint64_t, Measure>{}) {}

    ~PairScan();
    PairScan(const PairScan&) = delete;
    PairScan& operator=(const PairScan&) = delete;

    std::map<IdPair, PairState> run(Examples& examples);

private:
    std::vector<std::size_t> candidates(GEOSSTRtree* tree, std::size_t i) const;
    void relate(std::size_t i, std::size_t j, std::map<IdPair, PairState>& out,
                Examples& examples) const;
    Measure overlay_measure(const GEOSGeometry* a, const GEOSGeometry* b, bool boundaries) const;
    Measure area_of(const GEOSGeometry* g) const;
    void point_on(const GEOSGeometry* g, Measure& m) const;

    Measure shared_length(std::size_t i, std::size_t j) const;
    const GEOSPreparedGeometry* prepared(std::size_t i) const;
    Relation classify(std::size_t i, std::size_t j) const;

    GeosContext& m_ctx;
    const Side& m_side;
    double m_t;
    bool m_measure_shared;
    const std::map<IdPair, PairState>* m_before;
    std::unordered_map<std::uint64_t, Measure> m_common; ///< see common_segments()
    /// Prepared (indexed) geometries, built on first use: a large polygon overlapping
    /// thousands of small ones is indexed once instead of once per pair.
    mutable std::unordered_map<std::size_t, const GEOSPreparedGeometry*> m_prepared;
};

PairScan::~PairScan() {
    for (const auto& [i, p] : m_prepared)
        GEOSPreparedGeom_destroy_r(m_ctx.get(), p);
}

const GEOSPreparedGeometry* PairScan::prepared(std::size_t i) const {
    auto [it, added] = m_prepared.try_emplace(i, nullptr);
    if (added)
        it->second = GEOSPrepare_r(m_ctx.get(), m_side.features[i].pair_geom());
    return it->second;
}

// Cheap prepared predicates settle the common cases (disjoint, one inside the other) before a
// full relate, which GEOS 3.11 computes from scratch for every pair.
Relation PairScan::classify(std::size_t i, std::size_t j) const {
    const SideFeature& a = m_side.features[i];
    const SideFeature& b = m_side.features[j];
    const bool a_larger = a.seg_end - a.seg_begin >= b.seg_end - b.seg_begin;
    const GEOSPreparedGeometry* large = prepared(a_larger ? i : j);
    const GEOSGeometry* small = (a_larger ? b : a).pair_geom();
    Relation r;
    if (large && GEOSPreparedIntersects_r(m_ctx.get(), large, small) == 0)
        return r;
    if (large && GEOSPreparedContainsProperly_r(m_ctx.get(), large, small) == 1) {
        r.interiors_meet = true;
        r.inside = small;
        return r;
    }
    char* matrix = GEOSRelate_r(m_ctx.get(), a.pair_geom(), b.pair_geom());
    if (!matrix) {
        r.failed = true;
        return r;
    }
    r.interiors_meet = matrix[0] == '2';
    r.boundaries_share_line = matrix[4] == '1';
    GEOSFree_r(m_ctx.get(), matrix);
    return r;
}

Measure PairScan::shared_length(std::size_t i, std::size_t j) const {
    auto it = m_common.find(pair_key(i, j));
    if (it != m_common.end() && it->second.value > 2.0 * m_t)
        return it->second;
    return overlay_measure(m_side.features[i].pair_geom(), m_side.features[j].pair_geom(), true);
}

std::vector<std::size_t> PairScan::candidates(GEOSSTRtree* tree, std::size_t i) const {
    std::vector<std::size_t> found;
    auto collect = [](void* item, void* data) {
        static_cast<std::vector<std::size_t>*>(data)->push_back(*static_cast<std::size_t*>(item));
    };
    GEOSSTRtree_query_r(m_ctx.get(), tree, m_side.features[i].pair_geom(), collect, &found);
    return found;
}

std::map<IdPair, PairState> PairScan::run(Examples& examples) {
    std::vector<std::size_t> polygons;
    for (std::size_t i = 0; i < m_side.features.size(); ++i)
        if (m_side.features[i].present() && m_side.features[i].polygonal &&
            m_side.features[i].pair_geom())
            polygons.push_back(i);
    GEOSSTRtree* tree = GEOSSTRtree_create_r(m_ctx.get(), 10);
    for (std::size_t& i : polygons)
        GEOSSTRtree_insert_r(m_ctx.get(), tree, m_side.features[i].pair_geom(), &i);
    std::map<IdPair, PairState> states;
    for (std::size_t i : polygons)
        for (std::size_t j : candidates(tree, i))
            if (i < j && m_side.features[i].id != m_side.features[j].id)
                relate(i, j, states, examples);
    GEOSSTRtree_destroy_r(m_ctx.get(), tree);
    return states;
}

// Area of a ∩ b, or with `boundaries` the length of boundary(a) ∩ boundary(b), and a point
// on it for messages. A failing overlay counts as "yes, they meet" (+inf): a checker must not
// pass what it could not measure.
Measure PairScan::overlay_measure(const GEOSGeometry* a, const GEOSGeometry* b,
                                  bool boundaries) const {
    GEOSContextHandle_t h = m_ctx.get();
    Measure m{std::numeric_limits<double>::infinity(), 0.0, 0.0};
    GeomPtr both;
    if (boundaries) {
        GeomPtr ba = own(m_ctx, GEOSBoundary_r(h, a));
        GeomPtr bb = own(m_ctx, GEOSBoundary_r(h, b));
        if (ba && bb)
            both = own(m_ctx, GEOSIntersection_r(h, ba.get(), bb.get()));
    } else {
        both = own(m_ctx, GEOSIntersection_r(h, a, b));
    }
    if (!both || !(boundaries ? GEOSLength_r(h, both.get(), &m.value)
                              : GEOSArea_r(h, both.get(), &m.value)))
        return m;
    point_on(both.get(), m);
    return m;
}

Measure PairScan::area_of(const GEOSGeometry* g) const {
    Measure m{std::numeric_limits<double>::infinity(), 0.0, 0.0};
    if (GEOSArea_r(m_ctx.get(), g, &m.value))
        point_on(g, m);
    return m;
}

void PairScan::point_on(const GEOSGeometry* g, Measure& m) const {
    GEOSContextHandle_t h = m_ctx.get();
    if (GeomPtr p = own(m_ctx, GEOSPointOnSurface_r(h, g)); p && GEOSisEmpty_r(h, p.get()) == 0) {
        GEOSGeomGetX_r(h, p.get(), &m.x);
        GEOSGeomGetY_r(h, p.get(), &m.y);
    }
}

void PairScan::relate(std::size_t i, std::size_t j, std::map<IdPair, PairState>& out,
                      Examples& examples) const {
    const SideFeature& a = m_side.features[i];
    const SideFeature& b = m_side.features[j];
    const Relation r = classify(i, j);
    const IdPair key = std::minmax(a.id, b.id);
    if (r.failed) {
        examples.add("geos", "GEOS relate failed for ids " + std::to_string(a.id) + " and " +
                                 std::to_string(b.id) + ": " + m_ctx.last_error());
        // Unmeasured counts as overlapping: on the input side an output overlap is then not
        // called new (GEOS failed on an invalid input, found by fuzz_snap), on the output side
        // it is one unless the input overlapped (a checker must not pass what it cannot see).
        out[key].overlap = true;
        return;
    }
    PairState state;
    if (r.interiors_meet && m_before && m_before->count(key) && m_before->at(key).overlap) {
        state.overlap = true;
    } else if (r.interiors_meet) {
        const Measure m = r.inside ? area_of(r.inside) : overlay_measure(a.pair_geom(), b.pair_geom(), false);
        // Relate says the interiors meet in an area; an overlay area of exactly 0 is then an
        // overlay that lost it (GEOS at coordinates near 1e104, found by fuzz_snap), not "no
        // overlap": like a failing overlay, it counts as an overlap.
        state.overlap = m.value > 1e-9 * m_t * m_t || m.value == 0.0;
        state.x = m.x;
        state.y = m.y;
    }
    if (r.boundaries_share_line && !m_measure_shared) {
        state.shared = true;
    } else if (r.boundaries_share_line) {
        const Measure m = shared_length(i, j);
        // A shared piece shorter than 2t may legitimately shrink to a point: its ends can merge.
        state.shared = m.value > 2.0 * m_t;
        if (!state.overlap) {
            state.x = m.x;
            state.y = m.y;
        }
    }
    if (state.overlap || state.shared)
        out[key] = state;
}

bool polygonal_output(const Side& out, std::int64_t id) {
    auto it = out.by_id.find(id);
    return it != out.by_id.end() && out.features[it->second].present() &&
           out.features[it->second].polygonal;
}

std::string pair_text(const IdPair& p) {
    return "ids " + std::to_string(p.first) + " and " + std::to_string(p.second);
}

} // namespace

void check_pairs(GeosContext& ctx, const Side& in, const Side& out, double t,
                 const std::vector<std::int64_t>& exempt, const std::vector<std::int64_t>& lost_reported,
                 const std::vector<std::int64_t>& unfinished, ContractReport& report, Examples& examples) {
    const auto before = PairScan(ctx, in, t, true).run(examples);
    const auto after = PairScan(ctx, out, t, false, &before).run(examples);
    auto state = [](const std::map<IdPair, PairState>& states, const IdPair& key) {
        auto it = states.find(key);
        return it == states.end() ? PairState{} : it->second;
    };
    const auto unfinished_at = [&](std::int64_t id) {
        return std::find(unfinished.begin(), unfinished.end(), id) != unfinished.end();
    };
    for (const auto& [key, now] : after) {
        if (now.overlap && !state(before, key).overlap) {
            if (unfinished_at(key.first) && unfinished_at(key.second)) {
                ++report.n_overlaps_new_reported;
                continue;
            }
            ++report.n_overlaps_new;
            examples.add("overlap", "new overlap: " + pair_text(key) + " at " +
                                        point_text(now.x, now.y));
        }
    }
    for (const auto& [key, was] : before) {
        if (!was.shared || !polygonal_output(out, key.first) || !polygonal_output(out, key.second))
            continue;
        // A part the engine reported as collapsed takes its shared boundary with it.
        const auto reported = [&](std::int64_t id) {
            return std::find(exempt.begin(), exempt.end(), id) != exempt.end();
        };
        if (reported(key.first) || reported(key.second)) continue;
        const PairState now = state(after, key);
        if (now.shared && !(now.overlap && !was.overlap))
            continue;
        // Still shared, but folded over each other where the run stopped short: counted above.
        if (now.shared && unfinished_at(key.first) && unfinished_at(key.second))
            continue;
        const auto lost_said = [&](std::int64_t id) {
            return std::find(lost_reported.begin(), lost_reported.end(), id) != lost_reported.end();
        };
        if (!now.shared && (lost_said(key.first) || lost_said(key.second))) {
            ++report.n_shared_lost_reported;
            continue;
        }
        ++report.n_shared_lost;
        examples.add("shared", std::string(now.shared ? "shared boundary now overlaps: "
                                                       : "shared boundary lost: ") +
                                   pair_text(key) + " near " + point_text(was.x, was.y));
    }
}

} // namespace trisnap::checker_detail
