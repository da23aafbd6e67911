#pragma once
// Conversion between OGR geometries and the engine's plain geometry types.
// Accepted: Polygon, MultiPolygon, LineString, MultiLineString, with or without Z (M is
// dropped), and their curve counterparts (linearised with GDAL's defaults first).
#include "core/geometry.hpp"

#include <ogr_geometry.h>

namespace trisnap {

/// What the reader should do with one input geometry.
enum class GeometryVerdict {
    snap,         ///< converted; goes to the engine
    pass_through, ///< points and multipoints: written unchanged, no problem
    unsupported,  ///< other types (collections, TINs...): written unchanged, problem 108
    empty,        ///< null or empty: written with its geometry as-is, problem 107
    non_finite,   ///< NaN or infinite coordinate: rejected (not written), problem 106
};

/// What a conversion noticed without rejecting the geometry.
struct ReadNotes {
    std::size_t non_finite_z = 0; ///< vertices whose NaN or infinite Z became "no Z" (NaN)
};

/// Converts `source` into `out` when the verdict is `snap`; `source` may be null. A NaN or
/// infinite Z becomes NaN ("no Z"), counted in `notes`.
GeometryVerdict from_ogr(const OGRGeometry* source, Geometry& out, ReadNotes& notes);
GeometryVerdict from_ogr(const OGRGeometry* source, Geometry& out);

/// Builds the OGR geometry for an engine result. `like` is the input's flattened type: a
/// single-part input stays single-part when the result has one part, else it becomes multi.
/// Returns null for an empty result.
OGRGeometry* to_ogr(const Geometry& geometry, OGRwkbGeometryType like);

/// Whether to_ogr(geometry, like) makes a multi-part geometry (io/gpkg_rows.hpp encodes the same).
bool written_multi(const Geometry& geometry, OGRwkbGeometryType like);

/// Number of points in any geometry (curves counted as stored); 0 for null.
std::size_t count_vertices(const OGRGeometry* geometry);

} // namespace trisnap
