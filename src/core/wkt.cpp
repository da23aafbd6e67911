#include "core/wkt.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

namespace trisnap {
namespace {

/// Recursive-descent reader over one WKT string. Positions in messages are 0-based character
/// offsets, because one-line WKT in a golden file is easiest to debug by counting characters.
class WktParser {
public:
    explicit WktParser(std::string_view text) : m_text(text) {}

    Geometry parse();

private:
    std::string_view m_text;
    std::size_t m_pos = 0;
    int m_dims = 0; ///< 0 until the first coordinate (or a Z keyword) fixes it to 2 or 3

    [[noreturn]] void fail(const std::string& what) const;
    Geometry::Type header();
    void skip_space();
    std::string word();
    bool accept(char c);
    void expect(char c);
    bool accept_empty();
    double number();
    Coord coord();
    Path path();
    Polygon polygon();
    template <class Item, class ReadItem> std::vector<Item> list(ReadItem read_item);
};

void WktParser::fail(const std::string& what) const {
    std::string found = m_pos < m_text.size() ? "'" + std::string(1, m_text[m_pos]) + "'"
                                              : std::string("end of text");
    throw std::invalid_argument("WKT error at position " + std::to_string(m_pos) + ": " + what +
                                ", found " + found);
}

void WktParser::skip_space() {
    while (m_pos < m_text.size() && std::isspace(static_cast<unsigned char>(m_text[m_pos])))
        ++m_pos;
}

std::string WktParser::word() {
    skip_space();
    std::string out;
    while (m_pos < m_text.size() && std::isalpha(static_cast<unsigned char>(m_text[m_pos])))
        out += static_cast<char>(std::toupper(static_cast<unsigned char>(m_text[m_pos++])));
    return out;
}

bool WktParser::accept(char c) {
    skip_space();
    if (m_pos < m_text.size() && m_text[m_pos] == c) {
        ++m_pos;
        return true;
    }
    return false;
}

void WktParser::expect(char c) {
    if (!accept(c))
        fail(std::string("expected '") + c + "'");
}

bool WktParser::accept_empty() {
    skip_space();
    const std::size_t saved = m_pos;
    if (word() == "EMPTY")
        return true;
    m_pos = saved;
    return false;
}

double WktParser::number() {
    skip_space();
    const char* first = m_text.data() + m_pos;
    const char* last = m_text.data() + m_text.size();
    // from_chars rejects a leading '+', which some writers emit.
    if (first != last && *first == '+')
        ++first;
    double value = 0.0;
    auto [end, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range) {
        m_pos = static_cast<std::size_t>(first - m_text.data());
        fail("number out of range");
    }
    if (ec != std::errc() || end == first)
        fail("expected a number");
    m_pos = static_cast<std::size_t>(end - m_text.data());
    return value;
}

Coord WktParser::coord() {
    Coord c;
    c.x = number();
    c.y = number();
    skip_space();
    bool more = m_pos < m_text.size() && m_text[m_pos] != ',' && m_text[m_pos] != ')';
    if (m_dims == 0)
        m_dims = more ? 3 : 2;
    if (m_dims == 3)
        c.z = number();
    return c;
}

template <class Item, class ReadItem> std::vector<Item> WktParser::list(ReadItem read_item) {
    std::vector<Item> items;
    expect('(');
    do {
        items.push_back(read_item());
    } while (accept(','));
    expect(')');
    return items;
}

Path WktParser::path() {
    return list<Coord>([this] { return coord(); });
}

Polygon WktParser::polygon() {
    return Polygon{list<Path>([this] { return path(); })};
}

Geometry::Type WktParser::header() {
    using Type = Geometry::Type;
    skip_space();
    const std::size_t type_pos = m_pos;
    const std::string type = word();
    const std::size_t after_type = m_pos;
    skip_space();
    const std::size_t dim_pos = m_pos;
    const std::string dim = word();
    if (dim == "Z") {
        m_dims = 3;
    } else if (dim == "M" || dim == "ZM") {
        m_pos = dim_pos;
        fail("measured (M) coordinates are not supported");
    } else {
        m_pos = after_type;
    }
    if (type == "POLYGON")
        return Type::Polygon;
    if (type == "MULTIPOLYGON")
        return Type::MultiPolygon;
    if (type == "LINESTRING")
        return Type::LineString;
    if (type == "MULTILINESTRING")
        return Type::MultiLineString;
    if (type == "GEOMETRYCOLLECTION")
        return Type::Empty; // only the empty collection is accepted, in parse()
    m_pos = type_pos;
    fail("expected POLYGON, MULTIPOLYGON, LINESTRING or MULTILINESTRING");
}

Geometry WktParser::parse() {
    using Type = Geometry::Type;
    Geometry g;
    g.type = header();
    if (!accept_empty()) {
        if (g.type == Type::Empty)
            fail("only GEOMETRYCOLLECTION EMPTY is supported");
        if (g.type == Type::Polygon)
            g.polygons.push_back(polygon());
        else if (g.type == Type::MultiPolygon)
            g.polygons = list<Polygon>([this] { return polygon(); });
        else if (g.type == Type::LineString)
            g.lines.push_back(path());
        else
            g.lines = list<Path>([this] { return path(); });
    }
    g.has_z = m_dims == 3;
    skip_space();
    if (m_pos != m_text.size())
        fail("unexpected text after the geometry");
    return g;
}

// ---- writing ----

void append_double(std::string& out, double v, int digits) {
    char buf[64];
    std::to_chars_result r = digits >= 17
        ? std::to_chars(buf, buf + sizeof buf, v)
        : std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
    out.append(buf, r.ptr);
}

void append_coord(std::string& out, const Coord& c, bool has_z, int digits) {
    append_double(out, c.x, digits);
    out += ' ';
    append_double(out, c.y, digits);
    if (has_z) {
        out += ' ';
        if (std::isnan(c.z))
            out += "NaN"; // a 2D point inside a Z geometry; from_chars reads it back
        else
            append_double(out, c.z, digits);
    }
}

void append_path(std::string& out, const Path& path, bool has_z, int digits) {
    out += '(';
    for (std::size_t i = 0; i < path.size(); ++i) {
        if (i > 0)
            out += ", ";
        append_coord(out, path[i], has_z, digits);
    }
    out += ')';
}

void append_polygon(std::string& out, const Polygon& polygon, bool has_z, int digits) {
    out += '(';
    for (std::size_t i = 0; i < polygon.rings.size(); ++i) {
        if (i > 0)
            out += ", ";
        append_path(out, polygon.rings[i], has_z, digits);
    }
    out += ')';
}

const char* type_name(Geometry::Type type) {
    switch (type) {
    case Geometry::Type::Polygon: return "POLYGON";
    case Geometry::Type::MultiPolygon: return "MULTIPOLYGON";
    case Geometry::Type::LineString: return "LINESTRING";
    case Geometry::Type::MultiLineString: return "MULTILINESTRING";
    case Geometry::Type::Empty: break;
    }
    return "GEOMETRYCOLLECTION";
}

template <class Item, class AppendItem>
void append_list(std::string& out, const std::vector<Item>& items, AppendItem append_item) {
    out += '(';
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0)
            out += ", ";
        append_item(items[i]);
    }
    out += ')';
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
        s.remove_suffix(1);
    return s;
}

Feature parse_feature_line(std::string_view line, std::size_t line_no) {
    auto where = [&] { return "line " + std::to_string(line_no) + ": "; };
    std::size_t semi = line.find(';');
    if (semi == std::string_view::npos)
        throw std::invalid_argument(where() + "expected '<id>;<WKT>'");
    std::string_view id_text = trim(line.substr(0, semi));
    Feature f;
    auto [end, ec] = std::from_chars(id_text.data(), id_text.data() + id_text.size(), f.id);
    if (ec != std::errc() || end != id_text.data() + id_text.size() || id_text.empty())
        throw std::invalid_argument(where() + "bad feature id '" + std::string(id_text) + "'");
    try {
        f.geometry = read_wkt(line.substr(semi + 1));
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where() + e.what());
    }
    return f;
}

} // namespace

Geometry read_wkt(std::string_view text) {
    return WktParser(text).parse();
}

std::string to_wkt(const Geometry& g, int significant_digits) {
    using Type = Geometry::Type;
    const int digits = significant_digits < 1 ? 1 : significant_digits;
    // A single-part type holding several parts is written as its multi type: a dump must
    // never drop data silently.
    Type type = g.type;
    if (type == Type::Polygon && g.polygons.size() > 1)
        type = Type::MultiPolygon;
    if (type == Type::LineString && g.lines.size() > 1)
        type = Type::MultiLineString;
    std::string out = type_name(type);
    if (g.has_z && type != Type::Empty)
        out += " Z";
    // Only the parts that match the type are written (the other vector should be empty).
    const bool polygonal = type == Type::Polygon || type == Type::MultiPolygon;
    if (type == Type::Empty || (polygonal ? g.polygons.empty() : g.lines.empty()))
        return out + " EMPTY";
    out += ' ';
    auto polygon = [&](const Polygon& p) { append_polygon(out, p, g.has_z, digits); };
    auto path = [&](const Path& p) { append_path(out, p, g.has_z, digits); };
    if (type == Type::Polygon)
        polygon(g.polygons.front());
    else if (type == Type::MultiPolygon)
        append_list(out, g.polygons, polygon);
    else if (type == Type::LineString)
        path(g.lines.front());
    else
        append_list(out, g.lines, path);
    return out;
}

std::vector<Feature> read_wkt_features(std::istream& in) {
    std::vector<Feature> features;
    std::string line;
    for (std::size_t line_no = 1; std::getline(in, line); ++line_no) {
        std::string_view view = trim(line);
        if (view.empty() || view.front() == '#')
            continue;
        features.push_back(parse_feature_line(view, line_no));
    }
    return features;
}

} // namespace trisnap
