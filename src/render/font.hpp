#pragma once
// A 5x7 pixel font for printable ASCII, drawn for trisnap (labels in PNG output; SVG uses real
// text). Each glyph is 7 rows of 5 bits, most significant of the 5 = leftmost pixel.
#include <array>
#include <cstdint>

namespace trisnap::render {

inline constexpr int k_glyph_width = 5;
inline constexpr int k_glyph_height = 7;
inline constexpr int k_glyph_advance = 6; ///< pixels per character at scale 1

/// The rows of character `c`; characters outside 32..126 map to '?'.
const std::array<std::uint8_t, 7>& glyph(char c);

/// Rows by which a glyph with a descender (g, p, q, y) sits lower than the others.
int glyph_drop(char c);

} // namespace trisnap::render
