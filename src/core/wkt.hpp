#pragma once
// Well-known text for the engine's plain geometry types: golden test cases, debugging dumps and
// the `<id>;<WKT>` feature files used by tests and benchmarks. Standard library only, so any
// module (and the tests) can use it without GDAL.
#include "core/geometry.hpp"

#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace trisnap {

/// Parses POLYGON, MULTIPOLYGON, LINESTRING, MULTILINESTRING (each optionally with ` Z`, or
/// three ordinates without the keyword), `<type> EMPTY` and `GEOMETRYCOLLECTION EMPTY`.
/// Keywords are case-insensitive. Rings are kept exactly as written: an unclosed ring stays
/// unclosed so the engine can report it. Throws std::invalid_argument with a one-line message
/// naming the character position (0-based) on text it does not understand.
Geometry read_wkt(std::string_view text);

/// Writes `geometry` as WKT. With significant_digits == 17 every double is written in the
/// shortest form that reads back to the same value (std::to_chars), so read_wkt(to_wkt(g))
/// reproduces g bit for bit. Fewer digits round (%.Ng style), for readable dumps.
std::string to_wkt(const Geometry& geometry, int significant_digits = 17);

/// Reads one feature per line as `<id>;<WKT>`. Blank lines and lines starting with '#' are
/// skipped. Throws std::invalid_argument naming the line number on a malformed line.
std::vector<Feature> read_wkt_features(std::istream& in);

} // namespace trisnap
