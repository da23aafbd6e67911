#pragma once
// A drawing surface in pixel coordinates (x right, y down), written either as SVG text or as a
// PNG rasterised here. Both take the same calls, so the two outputs show the same picture.
#include "render/types.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace trisnap::render {

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

struct Style {
    std::optional<Rgba> fill;   ///< polygons only, even-odd rule
    std::optional<Rgba> stroke; ///< opaque colours only (joins are drawn twice)
    double width = 1;
};

enum class Anchor { start, middle, end };

using PixelRings = std::vector<std::vector<XY>>;

class Canvas {
public:
    Canvas(int width, int height) : m_width(width), m_height(height) {}
    virtual ~Canvas() = default;
    int width() const { return m_width; }
    int height() const { return m_height; }

    /// Drawing until end_clip() is limited to `px`; clips do not nest.
    virtual void begin_clip(const Box& px) = 0;
    virtual void end_clip() = 0;
    /// One feature: rings closed (polygon, filled even-odd) or open (lines). `cls` names the
    /// element class in SVG (`in`, `out`, `site-drift`, ...) so tests and CSS can find it.
    virtual void path(const PixelRings& rings, bool closed, const Style& style, const char* cls) = 0;
    virtual void circle(XY centre, double radius, const Style& style, const char* cls) = 0;
    virtual void rect(const Box& px, const Style& style, const char* cls) = 0;
    /// ASCII text, `size` = integer scale (1: 6 px per character, 7 px capitals); y = baseline.
    virtual void text(XY at, const std::string& text, int size, Rgba colour, Anchor anchor) = 0;
    /// The picture file's bytes (SVG text, PNG); throws io_error naming `path` (the picture to be).
    virtual std::string encode(const std::string& path) = 0;

    static double text_width(const std::string& text, int size) { return 6.0 * size * static_cast<double>(text.size()); }

protected:
    int m_width;
    int m_height;
};

std::unique_ptr<Canvas> make_svg_canvas(int width, int height, Rgba background);
std::unique_ptr<Canvas> make_png_canvas(int width, int height, Rgba background);

} // namespace trisnap::render
