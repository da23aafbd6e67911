#pragma once
// GEOS plumbing for the contract checker: a reentrant context, owning pointers, and one side
// (input or output) of a check read from WKT into GEOS geometries plus a flat segment list.
#include "contract_checker.hpp"

#include <geos_c.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace trisnap::checker_detail {

/// One GEOS_init_r handle whose errors are kept as text instead of printed.
class GeosContext {
public:
    GeosContext();
    ~GeosContext();
    GeosContext(const GeosContext&) = delete;
    GeosContext& operator=(const GeosContext&) = delete;

    GEOSContextHandle_t get() const { return m_handle; }
    const std::string& last_error() const { return m_last_error; }

private:
    static void on_error(const char* message, void* self);
    GEOSContextHandle_t m_handle = nullptr;
    std::string m_last_error;
};

struct GeomDeleter {
    GEOSContextHandle_t handle = nullptr;
    void operator()(GEOSGeometry* g) const { GEOSGeom_destroy_r(handle, g); }
};
using GeomPtr = std::unique_ptr<GEOSGeometry, GeomDeleter>;

inline GeomPtr own(const GeosContext& ctx, GEOSGeometry* g) {
    return GeomPtr(g, GeomDeleter{ctx.get()});
}

/// A segment of a ring or line; `feature` indexes Side::features.
struct Segment {
    double ax, ay, bx, by;
    std::uint32_t feature;
};

struct SideFeature {
    std::int64_t id = 0;
    GeomPtr geom;              ///< null when the WKT did not parse or was empty
    GeomPtr repaired;          ///< valid polygonal stand-in for pair tests; null when not needed
    bool polygonal = false;
    bool lineal = false;
    std::string parse_error;   ///< GEOS's reason when the WKT did not parse
    std::size_t seg_begin = 0; ///< this feature's segments are [seg_begin, seg_end)
    std::size_t seg_end = 0;

    bool present() const { return geom != nullptr; }
    const GEOSGeometry* pair_geom() const { return repaired ? repaired.get() : geom.get(); }
};

struct Side {
    std::vector<SideFeature> features;
    std::vector<Segment> segments;
    std::unordered_map<std::int64_t, std::size_t> by_id; ///< first feature with each id
};

/// Reads every feature. With `strict` (the input side) a WKT that does not parse throws
/// std::invalid_argument; otherwise the reason is kept in SideFeature::parse_error. A feature
/// with a coordinate beyond `magnitude_limit` in absolute value is left unread the same way
/// (accounted for, not measured).
Side load_side(GeosContext& ctx, const std::vector<CheckedFeature>& features, bool strict,
               double magnitude_limit = std::numeric_limits<double>::infinity());

/// GEOS's reason when a present feature is invalid, else an empty string.
std::string invalid_reason(const GeosContext& ctx, const SideFeature& feature);

} // namespace trisnap::checker_detail
