#pragma once
// SQL text for SQLite statements built by hand (the GeoPackage R-tree's rows, the read's second
// reader): a name or a string between quotes, a quote inside doubled.
#include <string>

namespace trisnap {

/// `text` between `quote`s, a quote inside doubled.
inline std::string sql_quoted(const std::string& text, char quote)
{
    std::string out(1, quote);
    for (const char c : text) {
        out += c;
        if (c == quote) {
            out += quote;
        }
    }
    return out + quote;
}

/// An SQL identifier: "name".
inline std::string sql_identifier(const std::string& name) { return sql_quoted(name, '"'); }

/// An SQL string: 'text'.
inline std::string sql_literal(const std::string& text) { return sql_quoted(text, '\''); }

} // namespace trisnap
