#include "peer_xml.hpp"

#include <cctype>
#include <cstdlib>
#include <string>

namespace trisnap {
namespace {

std::string trim(std::string_view s) {
    std::size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b])))
        ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])))
        --e;
    return std::string(s.substr(b, e - b));
}

/// Text of the first <tag>...</tag> (or <tag attr...>...</tag>) in `s`; "" when absent.
std::string element_text(std::string_view s, std::string_view tag) {
    std::string open("<"), close("</");
    open.append(tag);
    close.append(tag).append(">");
    std::size_t at = 0;
    while ((at = s.find(open, at)) != std::string_view::npos) {
        const char next = at + open.size() < s.size() ? s[at + open.size()] : '\0';
        if (next == '>' || std::isspace(static_cast<unsigned char>(next)))
            break;
        at += open.size(); // a longer tag name sharing the prefix
    }
    if (at == std::string_view::npos)
        return {};
    const std::size_t body = s.find('>', at);
    const std::size_t end = s.find(close, body);
    if (body == std::string_view::npos || end == std::string_view::npos)
        return {};
    return trim(s.substr(body + 1, end - body - 1));
}

/// Value of attribute `name` ('...' or "...") in the first tag starting with `tag_open`.
std::string attribute(std::string_view s, std::string_view tag_open, std::string_view name) {
    const std::size_t tag = s.find(tag_open);
    if (tag == std::string_view::npos)
        return {};
    const std::string_view t = s.substr(tag, s.find('>', tag) - tag);
    std::string key(" ");
    key.append(name).append("=");
    const std::size_t at = t.find(key);
    if (at == std::string_view::npos)
        return {};
    const std::size_t q = at + name.size() + 2;
    const std::size_t end = t.find(t[q], q + 1);
    return std::string(t.substr(q + 1, end - q - 1));
}

double grid_of_case(std::string_view body, double run_grid) {
    const std::string arg3 = attribute(body, "<op ", "arg3");
    if (!arg3.empty() && std::atof(arg3.c_str()) > 0)
        return 1.0 / std::atof(arg3.c_str());
    const std::string arg2 = attribute(body, "<op ", "arg2");
    if (!arg2.empty() && std::atof(arg2.c_str()) < 0)
        return -std::atof(arg2.c_str());
    return run_grid;
}

} // namespace

std::vector<XmlCase> parse_xml_cases(std::string_view xml) {
    const std::string scale = attribute(xml, "<precisionModel", "scale");
    const double run_grid = scale.empty() ? 0.0 : 1.0 / std::atof(scale.c_str());
    std::vector<XmlCase> cases;
    std::size_t at = 0;
    while ((at = xml.find("<case>", at)) != std::string_view::npos) {
        const std::size_t end = xml.find("</case>", at);
        const std::string_view body = xml.substr(at, end - at);
        cases.push_back({element_text(body, "desc"), element_text(body, "a"),
                         element_text(body, "b"), grid_of_case(body, run_grid)});
        at = end;
    }
    return cases;
}

bool is_snappable_wkt(std::string_view wkt) {
    std::string word;
    for (char c : wkt) {
        if (!std::isalpha(static_cast<unsigned char>(c)))
            break;
        word += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    return word == "POLYGON" || word == "MULTIPOLYGON" || word == "LINESTRING" ||
           word == "MULTILINESTRING";
}

} // namespace trisnap
