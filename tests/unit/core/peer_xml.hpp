#pragma once
// The inputs of GEOS/JTS XML test files (`<run><precisionModel/><case><a>WKT</a><b>WKT</b>
// <test><op .../></test></case></run>`), read without regular expressions or an XML library:
// the files are machine-written and only a handful of tags matter to us.
#include <string>
#include <string_view>
#include <vector>

namespace trisnap {

struct XmlCase {
    std::string desc;
    std::string a;         ///< WKT of input A, trimmed ("" when absent)
    std::string b;         ///< WKT of input B, trimmed ("" when absent)
    double grid_size = 0;  ///< the precision of the case: 1/scale, or the negated reducePrecision
                           ///< argument; 0 when the case has none (floating precision)
};

/// Every <case> of an XML test file's text, in file order. A run-level
/// <precisionModel scale="s"/> gives grid size 1/s; an op's arg3 (snap-rounded overlay scale)
/// or a negative arg2 of reducePrecision (minus the grid size) overrides it per case.
std::vector<XmlCase> parse_xml_cases(std::string_view xml);

/// Whether `wkt` is a polygon, multipolygon, linestring or multilinestring (what the engine
/// snaps); points and collections are left out.
bool is_snappable_wkt(std::string_view wkt);

} // namespace trisnap
