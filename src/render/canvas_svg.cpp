// SVG output: one element per call, coordinates in pixels with one decimal, so files
// stay small and the same input gives the same bytes.
#include "render/canvas.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

namespace trisnap::render {
namespace {

/// A tenth of a pixel is below what any viewer shows.
std::string num(double v)
{
    std::string s = fmt::format("{:.1f}", std::round(v * 10) / 10);
    while (s.back() == '0') {
        s.pop_back();
    }
    if (s.back() == '.') {
        s.pop_back();
    }
    return s == "-0" ? "0" : s;
}

std::string colour(Rgba c) { return fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b); }

std::string escape(const std::string& text)
{
    std::string out;
    for (char c : text) {
        switch (c) {
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '&': out += "&amp;"; break;
        case '"': out += "&quot;"; break;
        default: out += (static_cast<unsigned char>(c) < 32 ? ' ' : c);
        }
    }
    return out;
}

std::string style_attributes(const Style& style, bool closed)
{
    std::string out;
    if (style.fill && closed) {
        out += " fill=\"" + colour(*style.fill) + "\" fill-rule=\"evenodd\"";
        if (style.fill->a != 255) {
            out += fmt::format(" fill-opacity=\"{:.2f}\"", style.fill->a / 255.0);
        }
    } else {
        out += " fill=\"none\"";
    }
    if (style.stroke) {
        out += " stroke=\"" + colour(*style.stroke) + "\" stroke-width=\"" + num(style.width) +
               "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
    }
    return out;
}

class SvgCanvas : public Canvas {
public:
    SvgCanvas(int width, int height, Rgba background) : Canvas(width, height)
    {
        m_body = fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                             "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
                             "viewBox=\"0 0 {0} {1}\" font-family=\"monospace\">\n"
                             "<rect class=\"background\" width=\"{0}\" height=\"{1}\" fill=\"{2}\"/>\n",
                             width, height, colour(background));
    }

    void begin_clip(const Box& px) override
    {
        close_group();
        m_body += fmt::format("<clipPath id=\"clip{0}\"><rect x=\"{1}\" y=\"{2}\" width=\"{3}\" height=\"{4}\"/></clipPath>\n"
                              "<g clip-path=\"url(#clip{0})\">\n",
                              m_clips++, num(px.xmin), num(px.ymin), num(px.width()), num(px.height()));
    }

    void end_clip() override
    {
        close_group();
        m_body += "</g>\n";
    }

    void path(const PixelRings& rings, bool closed, const Style& style, const char* cls) override
    {
        std::string d;
        for (const auto& ring : rings) {
            for (std::size_t i = 0; i < ring.size(); ++i) {
                d += (i == 0 ? (d.empty() ? "M" : " M") : " L") + num(ring[i].x) + " " + num(ring[i].y);
            }
            if (closed && !ring.empty()) {
                d += " Z";
            }
        }
        if (d.empty()) {
            return;
        }
        // Runs of paths with one style share a <g> carrying it: a big layer's file is mostly
        // coordinates, not repeated attributes.
        const std::string attributes = style_attributes(style, closed);
        if (!m_group || *m_group != attributes) {
            close_group();
            m_body += "<g" + attributes + ">\n";
            m_group = attributes;
        }
        m_body += fmt::format("<path class=\"{}\" d=\"{}\"/>\n", cls, d);
    }

    void circle(XY c, double r, const Style& style, const char* cls) override
    {
        close_group();
        m_body += fmt::format("<circle class=\"{}\" cx=\"{}\" cy=\"{}\" r=\"{}\"{}/>\n", cls, num(c.x), num(c.y), num(r),
                              style_attributes(style, true));
    }

    void rect(const Box& px, const Style& style, const char* cls) override
    {
        close_group();
        m_body += fmt::format("<rect class=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"{}/>\n", cls, num(px.xmin),
                              num(px.ymin), num(px.width()), num(px.height()), style_attributes(style, true));
    }

    void text(XY at, const std::string& text, int size, Rgba c, Anchor anchor) override
    {
        close_group();
        const char* a = anchor == Anchor::start ? "start" : anchor == Anchor::middle ? "middle" : "end";
        m_body += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"{}\" fill=\"{}\" text-anchor=\"{}\">{}</text>\n",
                              num(at.x), num(at.y), 10 * size, colour(c), a, escape(text));
    }

    std::string encode(const std::string&) override
    {
        close_group();
        return m_body + "</svg>\n";
    }

private:
    void close_group()
    {
        if (m_group) {
            m_body += "</g>\n";
        }
        m_group.reset();
    }

    std::string m_body;
    std::optional<std::string> m_group; ///< attributes of the open style group
    int m_clips = 0;
};

} // namespace

std::unique_ptr<Canvas> make_svg_canvas(int width, int height, Rgba background)
{
    return std::make_unique<SvgCanvas>(width, height, background);
}

} // namespace trisnap::render
