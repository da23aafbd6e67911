#include "checker_geos.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

namespace trisnap::checker_detail {

GeosContext::GeosContext() : m_handle(GEOS_init_r()) {
    GEOSContext_setErrorMessageHandler_r(m_handle, &GeosContext::on_error, this);
}

GeosContext::~GeosContext() {
    GEOS_finish_r(m_handle);
}

void GeosContext::on_error(const char* message, void* self) {
    static_cast<GeosContext*>(self)->m_last_error = message ? message : "";
}

namespace {

void add_sequence(const GeosContext& ctx, const GEOSGeometry* line, std::uint32_t feature,
                  std::vector<Segment>& out) {
    const GEOSCoordSequence* seq = GEOSGeom_getCoordSeq_r(ctx.get(), line);
    unsigned int n = 0;
    if (!seq || !GEOSCoordSeq_getSize_r(ctx.get(), seq, &n) || n == 0)
        return;
    double px = 0, py = 0;
    GEOSCoordSeq_getXY_r(ctx.get(), seq, 0, &px, &py);
    for (unsigned int i = 1; i < n; ++i) {
        double x = 0, y = 0;
        GEOSCoordSeq_getXY_r(ctx.get(), seq, i, &x, &y);
        // Repeated points make zero-length segments: they add no vertex and no edge.
        if (x != px || y != py)
            out.push_back(Segment{px, py, x, y, feature});
        px = x;
        py = y;
    }
}

void add_segments(const GeosContext& ctx, const GEOSGeometry* g, std::uint32_t feature,
                  std::vector<Segment>& out) {
    const int type = GEOSGeomTypeId_r(ctx.get(), g);
    if (type == GEOS_LINESTRING || type == GEOS_LINEARRING) {
        add_sequence(ctx, g, feature, out);
    } else if (type == GEOS_POLYGON) {
        add_sequence(ctx, GEOSGetExteriorRing_r(ctx.get(), g), feature, out);
        const int holes = GEOSGetNumInteriorRings_r(ctx.get(), g);
        for (int i = 0; i < holes; ++i)
            add_sequence(ctx, GEOSGetInteriorRingN_r(ctx.get(), g, i), feature, out);
    } else if (type == GEOS_MULTIPOLYGON || type == GEOS_MULTILINESTRING ||
               type == GEOS_GEOMETRYCOLLECTION) {
        const int parts = GEOSGetNumGeometries_r(ctx.get(), g);
        for (int i = 0; i < parts; ++i)
            add_segments(ctx, GEOSGetGeometryN_r(ctx.get(), g, i), feature, out);
    }
}

// The polygonal parts of a MakeValid result (which may also hold collapsed lines and points).
GeomPtr polygonal_parts(const GeosContext& ctx, GeomPtr g) {
    if (!g || GEOSGeomTypeId_r(ctx.get(), g.get()) != GEOS_GEOMETRYCOLLECTION)
        return g;
    std::vector<GEOSGeometry*> parts;
    for (int i = 0; i < GEOSGetNumGeometries_r(ctx.get(), g.get()); ++i) {
        const GEOSGeometry* part = GEOSGetGeometryN_r(ctx.get(), g.get(), i);
        const int type = GEOSGeomTypeId_r(ctx.get(), part);
        if (type == GEOS_POLYGON || type == GEOS_MULTIPOLYGON)
            parts.push_back(GEOSGeom_clone_r(ctx.get(), part));
    }
    GEOSGeometry* collection = GEOSGeom_createCollection_r(
        ctx.get(), GEOS_GEOMETRYCOLLECTION, parts.data(), static_cast<unsigned>(parts.size()));
    GeomPtr owned = own(ctx, collection);
    return own(ctx, GEOSUnaryUnion_r(ctx.get(), owned.get()));
}

// Distinct points of a ring (a ring of fewer than 3 has no area).
std::size_t distinct_points(const GeosContext& ctx, const GEOSGeometry* ring) {
    const GEOSCoordSequence* seq = GEOSGeom_getCoordSeq_r(ctx.get(), ring);
    unsigned int n = 0;
    if (!seq || !GEOSCoordSeq_getSize_r(ctx.get(), seq, &n))
        return 0;
    std::vector<std::pair<double, double>> pts(n);
    for (unsigned int i = 0; i < n; ++i)
        GEOSCoordSeq_getXY_r(ctx.get(), seq, i, &pts[i].first, &pts[i].second);
    std::sort(pts.begin(), pts.end());
    return static_cast<std::size_t>(std::unique(pts.begin(), pts.end()) - pts.begin());
}

// The polygons of g whose shell has an area: a polygon whose shell has fewer than 3 distinct
// points is nothing, holes included (they are holes of nothing). Null when none is left out.
GeomPtr without_pointless_shells(const GeosContext& ctx, const GEOSGeometry* g) {
    const int type = GEOSGeomTypeId_r(ctx.get(), g);
    if (type != GEOS_MULTIPOLYGON && type != GEOS_POLYGON)
        return nullptr;
    std::vector<GEOSGeometry*> kept;
    const int parts = type == GEOS_POLYGON ? 1 : GEOSGetNumGeometries_r(ctx.get(), g);
    for (int i = 0; i < parts; ++i) {
        const GEOSGeometry* poly = type == GEOS_POLYGON ? g : GEOSGetGeometryN_r(ctx.get(), g, i);
        if (distinct_points(ctx, GEOSGetExteriorRing_r(ctx.get(), poly)) >= 3)
            kept.push_back(GEOSGeom_clone_r(ctx.get(), poly));
    }
    if (static_cast<int>(kept.size()) == parts) {
        for (GEOSGeometry* k : kept)
            GEOSGeom_destroy_r(ctx.get(), k);
        return nullptr;
    }
    return own(ctx, GEOSGeom_createCollection_r(ctx.get(), GEOS_MULTIPOLYGON, kept.data(),
                                                static_cast<unsigned>(kept.size())));
}

using Edge = std::pair<std::pair<double, double>, std::pair<double, double>>;

// Every edge of every ring of g (a polygon or multipolygon), each as often as it is there.
void ring_edges(const GeosContext& ctx, const GEOSGeometry* g, std::vector<Edge>& edges,
                std::vector<GEOSGeometry*>& lines) {
    const int type = GEOSGeomTypeId_r(ctx.get(), g);
    const int parts = type == GEOS_POLYGON ? 1 : GEOSGetNumGeometries_r(ctx.get(), g);
    for (int i = 0; i < parts; ++i) {
        const GEOSGeometry* poly = type == GEOS_POLYGON ? g : GEOSGetGeometryN_r(ctx.get(), g, i);
        const int holes = GEOSGetNumInteriorRings_r(ctx.get(), poly);
        for (int k = -1; k < holes; ++k) {
            const GEOSGeometry* ring = k < 0 ? GEOSGetExteriorRing_r(ctx.get(), poly) : GEOSGetInteriorRingN_r(ctx.get(), poly, k);
            const GEOSCoordSequence* seq = GEOSGeom_getCoordSeq_r(ctx.get(), ring);
            unsigned int n = 0;
            if (!seq || !GEOSCoordSeq_getSize_r(ctx.get(), seq, &n) || n < 2)
                continue;
            std::pair<double, double> prev;
            GEOSCoordSeq_getXY_r(ctx.get(), seq, 0, &prev.first, &prev.second);
            for (unsigned int j = 1; j < n; ++j) {
                std::pair<double, double> next;
                GEOSCoordSeq_getXY_r(ctx.get(), seq, j, &next.first, &next.second);
                if (next != prev)
                    edges.emplace_back(prev, next);
                prev = next;
            }
            lines.push_back(GEOSGeom_createLineString_r(ctx.get(), GEOSCoordSeq_clone_r(ctx.get(), seq)));
        }
    }
}

// How many of the edges a ray from (x, y) towards +x crosses (half-open in y, so a vertex on
// the ray counts once).
std::size_t crossings(const std::vector<Edge>& edges, double x, double y) {
    std::size_t n = 0;
    for (const auto& [a, b] : edges) {
        if ((a.second > y) == (b.second > y))
            continue;
        const double at = a.first + (y - a.second) / (b.second - a.second) * (b.first - a.first);
        if (at > x)
            ++n;
    }
    return n;
}

// The area of g by the odd-even rule over all its rings, each edge counted as often as the
// rings run along it: the faces of the noded rings (GEOS's Node and Polygonize) whose inner
// point a ray leaves through an odd number of edges. Null when GEOS fails.
GeomPtr odd_even_area(const GeosContext& ctx, const GEOSGeometry* g) {
    const int type = GEOSGeomTypeId_r(ctx.get(), g);
    if (type != GEOS_MULTIPOLYGON && type != GEOS_POLYGON)
        return nullptr;
    std::vector<Edge> edges;
    std::vector<GEOSGeometry*> lines;
    ring_edges(ctx, g, edges, lines);
    if (std::find(lines.begin(), lines.end(), nullptr) != lines.end()) {
        for (GEOSGeometry* l : lines)
            if (l)
                GEOSGeom_destroy_r(ctx.get(), l);
        return nullptr;
    }
    const GeomPtr linework = own(ctx, GEOSGeom_createCollection_r(ctx.get(), GEOS_MULTILINESTRING, lines.data(),
                                                                   static_cast<unsigned>(lines.size())));
    const GeomPtr noded = linework ? own(ctx, GEOSNode_r(ctx.get(), linework.get())) : nullptr;
    if (!noded)
        return nullptr;
    const GEOSGeometry* pieces[] = {noded.get()};
    const GeomPtr faces = own(ctx, GEOSPolygonize_r(ctx.get(), pieces, 1));
    if (!faces)
        return nullptr;
    std::vector<GEOSGeometry*> kept;
    for (int i = 0; i < GEOSGetNumGeometries_r(ctx.get(), faces.get()); ++i) {
        const GEOSGeometry* face = GEOSGetGeometryN_r(ctx.get(), faces.get(), i);
        const GeomPtr inner = own(ctx, GEOSPointOnSurface_r(ctx.get(), face));
        double x = 0, y = 0;
        if (!inner || !GEOSGeomGetX_r(ctx.get(), inner.get(), &x) || !GEOSGeomGetY_r(ctx.get(), inner.get(), &y)) {
            for (GEOSGeometry* k : kept)
                GEOSGeom_destroy_r(ctx.get(), k);
            return nullptr;
        }
        if (crossings(edges, x, y) % 2 == 1)
            kept.push_back(GEOSGeom_clone_r(ctx.get(), face));
    }
    const GeomPtr collection = own(ctx, GEOSGeom_createCollection_r(ctx.get(), GEOS_MULTIPOLYGON, kept.data(),
                                                                    static_cast<unsigned>(kept.size())));
    if (!collection)
        return nullptr;
    // The kept faces share exactly the noded edges between them: a coverage, which GEOS merges
    // by dropping the shared edges. Its overlay union (GEOSUnaryUnion) lost a whole face of
    // 855,739 square units there once: a thin face whose corner two almost equal crossing
    // points made (found by fuzz_snap; the overlap the input had at that face looked new). A
    // union whose area is not the faces' is not taken.
    double faces_area = 0;
    if (!GEOSArea_r(ctx.get(), collection.get(), &faces_area))
        return nullptr;
    const auto same_area = [&](const GeomPtr& u) {
        double a = 0;
        return u && GEOSArea_r(ctx.get(), u.get(), &a) && std::abs(a - faces_area) <= 1e-9 * faces_area;
    };
    if (GeomPtr merged = own(ctx, GEOSCoverageUnion_r(ctx.get(), collection.get())); same_area(merged))
        return merged;
    if (GeomPtr merged = own(ctx, GEOSUnaryUnion_r(ctx.get(), collection.get())); same_area(merged))
        return merged;
    return nullptr;
}

// Inputs may be invalid (bowties, overlapping rings, holes outside their shell): GEOS overlay
// would throw on them, so pair tests run on a valid stand-in covering the area the engine gives
// them, by the odd-even rule over all of the feature's rings (odd_even_area). GEOS's LINEWORK
// repair is not that where edges run along each other or rings cross: it merges a doubled edge
// and alternates across it, where the rule counts it twice; on a self-crossing shell with a
// second ring mostly outside it, and on two shells sharing a doubled diagonal, it left out areas
// the engine (rightly, by the rule) keeps, and an overlap the input had looked new (both found
// by fuzz_snap). The STRUCTURE method would drop a hole lying outside its shell altogether.
// LINEWORK stays the fallback when GEOS fails.
// A polygon whose shell has no area is left out first, its holes with it: a hole of nothing
// cuts nothing (found by fuzz_snap: a degenerate shell's hole inside the feature's other polygon).
GeomPtr repair(const GeosContext& ctx, const GEOSGeometry* g) {
    const GeomPtr pruned = without_pointless_shells(ctx, g);
    if (pruned)
        g = pruned.get();
    if (GeomPtr area = odd_even_area(ctx, g))
        return area;
    GEOSMakeValidParams* params = GEOSMakeValidParams_create_r(ctx.get());
    GEOSMakeValidParams_setMethod_r(ctx.get(), params, GEOS_MAKE_VALID_LINEWORK);
    GeomPtr fixed = own(ctx, GEOSMakeValidWithParams_r(ctx.get(), g, params));
    GEOSMakeValidParams_destroy_r(ctx.get(), params);
    return polygonal_parts(ctx, std::move(fixed));
}

void read_feature(GeosContext& ctx, GEOSWKTReader* reader, const CheckedFeature& in,
                  bool strict, double magnitude_limit, SideFeature& f) {
    f.id = in.id;
    if (in.wkt.find_first_not_of(" \t\r\n") == std::string::npos)
        return;
    f.geom = own(ctx, GEOSWKTReader_read_r(ctx.get(), reader, in.wkt.c_str()));
    if (!f.geom) {
        f.parse_error = ctx.last_error();
        // Real layers hold rings GEOS refuses (fewer than 4 points); such an input feature is
        // only accounted for (output or problem), not measured. Text that is not WKT at all is
        // a broken test.
        const bool structural = f.parse_error.find("IllegalArgumentException") != std::string::npos;
        if (strict && !structural)
            throw std::invalid_argument("input feature " + std::to_string(in.id) +
                                        ": GEOS cannot read its WKT: " + f.parse_error);
        return;
    }
    if (GEOSisEmpty_r(ctx.get(), f.geom.get()) == 1) {
        f.geom.reset();
        return;
    }
    // Beyond the range the engine accepts (it refuses the feature: 109), GEOS is no judge: its
    // MakeValid ran for minutes on one invalid ring mixing 1e260 with 1e-300 (found by fuzz_snap
    // in the input's repair). Such a feature is only accounted for, as one GEOS cannot read.
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (GEOSGeom_getExtent_r(ctx.get(), f.geom.get(), &x0, &y0, &x1, &y1) == 1 &&
        !(std::max({std::abs(x0), std::abs(y0), std::abs(x1), std::abs(y1)}) <= magnitude_limit)) {
        f.geom.reset();
        f.parse_error = "coordinates beyond the range measured: accounted for only";
        return;
    }
    const int type = GEOSGeomTypeId_r(ctx.get(), f.geom.get());
    f.polygonal = type == GEOS_POLYGON || type == GEOS_MULTIPOLYGON;
    f.lineal = type == GEOS_LINESTRING || type == GEOS_MULTILINESTRING;
    if (f.polygonal && GEOSisValid_r(ctx.get(), f.geom.get()) != 1)
        f.repaired = repair(ctx, f.geom.get());
}

} // namespace

Side load_side(GeosContext& ctx, const std::vector<CheckedFeature>& features, bool strict,
               double magnitude_limit) {
    Side side;
    side.features.resize(features.size());
    GEOSWKTReader* reader = GEOSWKTReader_create_r(ctx.get());
    try {
        for (std::size_t i = 0; i < features.size(); ++i) {
            SideFeature& f = side.features[i];
            read_feature(ctx, reader, features[i], strict, magnitude_limit, f);
            side.by_id.emplace(f.id, i);
            f.seg_begin = side.segments.size();
            if (f.present())
                add_segments(ctx, f.geom.get(), static_cast<std::uint32_t>(i), side.segments);
            f.seg_end = side.segments.size();
        }
    } catch (...) {
        GEOSWKTReader_destroy_r(ctx.get(), reader);
        throw;
    }
    GEOSWKTReader_destroy_r(ctx.get(), reader);
    return side;
}

std::string invalid_reason(const GeosContext& ctx, const SideFeature& f) {
    if (!f.present())
        return {};
    if (GEOSisValid_r(ctx.get(), f.geom.get()) == 1)
        return {};
    char* reason = GEOSisValidReason_r(ctx.get(), f.geom.get());
    std::string text = reason ? reason : "invalid";
    GEOSFree_r(ctx.get(), reason);
    return text;
}

} // namespace trisnap::checker_detail
