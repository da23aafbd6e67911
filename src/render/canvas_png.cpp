// PNG output: an RGB buffer drawn here (even-odd scanline fill with 4 sub-scanlines and exact
// horizontal coverage, distance-based anti-aliased strokes, a 5x7 bitmap font) and written
// through GDAL's MEM and PNG drivers, so no image library is needed.
#include "render/canvas.hpp"

#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "render/font.hpp"

#include <cpl_vsi.h>
#include <gdal_priv.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>

namespace trisnap::render {
namespace {

constexpr int k_sub = 4; // sub-scanlines per pixel row

struct Edge {
    double x0, y0, x1, y1; // y0 < y1
};

/// The non-horizontal edges of the rings, each pointing down (y0 < y1), sorted by y0.
std::vector<Edge> downward_edges(const PixelRings& rings)
{
    std::vector<Edge> edges;
    for (const auto& ring : rings) {
        for (std::size_t i = 0; i < ring.size(); ++i) {
            const XY p = ring[i];
            const XY q = ring[(i + 1) % ring.size()];
            if (p.y < q.y) {
                edges.push_back({p.x, p.y, q.x, q.y});
            } else if (q.y < p.y) {
                edges.push_back({q.x, q.y, p.x, p.y});
            }
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.y0 < b.y0; });
    return edges;
}

/// The edges' bounding box.
Box edge_bounds(const std::vector<Edge>& edges)
{
    Box box;
    for (const Edge& e : edges) {
        box.add(XY{e.x0, e.y0});
        box.add(XY{e.x1, e.y1});
    }
    return box;
}

class RasterCanvas : public Canvas {
public:
    RasterCanvas(int width, int height, Rgba background)
        : Canvas(width, height), m_pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    {
        for (std::size_t i = 0; i < m_pixels.size(); i += 3) {
            m_pixels[i] = background.r;
            m_pixels[i + 1] = background.g;
            m_pixels[i + 2] = background.b;
        }
        end_clip();
    }

    void begin_clip(const Box& px) override
    {
        m_clip = {std::max(0.0, std::floor(px.xmin)), std::max(0.0, std::floor(px.ymin)),
                  std::min<double>(m_width, std::ceil(px.xmax)), std::min<double>(m_height, std::ceil(px.ymax))};
    }

    void end_clip() override { m_clip = {0, 0, static_cast<double>(m_width), static_cast<double>(m_height)}; }

    void path(const PixelRings& rings, bool closed, const Style& style, const char*) override
    {
        if (closed && style.fill) {
            fill(rings, *style.fill);
        }
        if (!style.stroke) {
            return;
        }
        for (const auto& ring : rings) {
            for (std::size_t i = 1; i < ring.size(); ++i) {
                stroke_segment(ring[i - 1], ring[i], style.width, *style.stroke);
            }
            if (closed && ring.size() > 2 && !(ring.front() == ring.back())) {
                stroke_segment(ring.back(), ring.front(), style.width, *style.stroke);
            }
            if (ring.size() == 1) {
                stroke_segment(ring[0], ring[0], style.width, *style.stroke);
            }
        }
    }

    void circle(XY c, double r, const Style& style, const char*) override
    {
        const double half = style.stroke ? style.width / 2 : 0;
        for_pixels(Box::around(c, r + half + 1), [&](int x, int y) {
            const double d = distance({x + 0.5, y + 0.5}, c);
            if (style.fill) {
                blend(x, y, *style.fill, std::clamp(r + 0.5 - d, 0.0, 1.0));
            }
            if (style.stroke) {
                blend(x, y, *style.stroke, std::clamp(half + 0.5 - std::abs(d - r), 0.0, 1.0));
            }
        });
    }

    void rect(const Box& px, const Style& style, const char*) override
    {
        if (style.fill) {
            fill({{{px.xmin, px.ymin}, {px.xmax, px.ymin}, {px.xmax, px.ymax}, {px.xmin, px.ymax}}}, *style.fill);
        }
        if (style.stroke) {
            const XY a{px.xmin, px.ymin}, b{px.xmax, px.ymin}, c{px.xmax, px.ymax}, d{px.xmin, px.ymax};
            for (auto [p, q] : {std::pair{a, b}, {b, c}, {c, d}, {d, a}}) {
                stroke_segment(p, q, style.width, *style.stroke);
            }
        }
    }

    void text(XY at, const std::string& text, int size, Rgba colour, Anchor anchor) override
    {
        double x = at.x;
        if (anchor != Anchor::start) {
            x -= text_width(text, size) / (anchor == Anchor::middle ? 2 : 1);
        }
        const int left = static_cast<int>(std::lround(x)), top = static_cast<int>(std::lround(at.y)) - k_glyph_height * size;
        for (std::size_t i = 0; i < text.size(); ++i) {
            const auto& rows = glyph(text[i]);
            const int gx = left + static_cast<int>(i) * k_glyph_advance * size;
            const int gy = top + glyph_drop(text[i]) * size;
            for (int row = 0; row < k_glyph_height; ++row) {
                for (int col = 0; col < k_glyph_width; ++col) {
                    if (rows[static_cast<std::size_t>(row)] & (0x10 >> col)) {
                        for (int dy = 0; dy < size; ++dy) {
                            for (int dx = 0; dx < size; ++dx) {
                                blend(gx + col * size + dx, gy + row * size + dy, colour, 1.0);
                            }
                        }
                    }
                }
            }
        }
    }

    std::string encode(const std::string& path) override;

private:
    void blend(int x, int y, Rgba c, double coverage)
    {
        if (coverage <= 0 || x < m_clip.xmin || y < m_clip.ymin || x >= m_clip.xmax || y >= m_clip.ymax) {
            return;
        }
        const double a = coverage * c.a / 255.0;
        std::uint8_t* p = &m_pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(m_width) + static_cast<std::size_t>(x)) * 3];
        p[0] = static_cast<std::uint8_t>(std::lround(p[0] * (1 - a) + c.r * a));
        p[1] = static_cast<std::uint8_t>(std::lround(p[1] * (1 - a) + c.g * a));
        p[2] = static_cast<std::uint8_t>(std::lround(p[2] * (1 - a) + c.b * a));
    }

    template <class F>
    void for_pixels(const Box& px, F&& f)
    {
        const int x0 = static_cast<int>(std::max(m_clip.xmin, std::floor(px.xmin)));
        const int x1 = static_cast<int>(std::min(m_clip.xmax, std::ceil(px.xmax)));
        const int y0 = static_cast<int>(std::max(m_clip.ymin, std::floor(px.ymin)));
        const int y1 = static_cast<int>(std::min(m_clip.ymax, std::ceil(px.ymax)));
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                f(x, y);
            }
        }
    }

    /// A thick segment with round caps: each pixel is covered by how far its centre lies inside.
    /// Rows are walked one by one over the segment's x range in that row, so the cost is
    /// proportional to length × width, not to the bounding box.
    void stroke_segment(XY a, XY b, double width, Rgba c)
    {
        const double half = width / 2, reach = half + 1;
        const int y0 = static_cast<int>(std::max(m_clip.ymin, std::floor(std::min(a.y, b.y) - reach)));
        const int y1 = static_cast<int>(std::min(m_clip.ymax, std::ceil(std::max(a.y, b.y) + reach)));
        for (int y = y0; y < y1; ++y) {
            double xa = std::min(a.x, b.x), xb = std::max(a.x, b.x);
            if (std::abs(b.y - a.y) > 1e-12) { // x range of the segment inside the row band
                const double t0 = std::clamp((y - reach - a.y) / (b.y - a.y), 0.0, 1.0);
                const double t1 = std::clamp((y + 1 + reach - a.y) / (b.y - a.y), 0.0, 1.0);
                xa = std::min(a.x + t0 * (b.x - a.x), a.x + t1 * (b.x - a.x));
                xb = std::max(a.x + t0 * (b.x - a.x), a.x + t1 * (b.x - a.x));
            }
            const int x0 = static_cast<int>(std::max(m_clip.xmin, std::floor(xa - reach)));
            const int x1 = static_cast<int>(std::min(m_clip.xmax, std::ceil(xb + reach)));
            for (int x = x0; x < x1; ++x) {
                blend(x, y, c, std::clamp(half + 0.5 - distance_to_segment({x + 0.5, y + 0.5}, a, b), 0.0, 1.0));
            }
        }
    }

    void fill(const PixelRings& rings, Rgba c);
    void add_span(std::vector<double>& cover, double xa, double xb) const;

    std::vector<std::uint8_t> m_pixels;
    Box m_clip;
};

void RasterCanvas::add_span(std::vector<double>& cover, double xa, double xb) const
{
    xa = std::max(xa, m_clip.xmin);
    xb = std::min(xb, m_clip.xmax);
    if (xb <= xa) {
        return;
    }
    const double w = 1.0 / k_sub;
    const auto ia = static_cast<std::size_t>(xa), ib = static_cast<std::size_t>(xb);
    if (ia == ib) {
        cover[ia] += (xb - xa) * w;
        return;
    }
    cover[ia] += (static_cast<double>(ia + 1) - xa) * w;
    for (std::size_t i = ia + 1; i < ib; ++i) {
        cover[i] += w;
    }
    if (ib < cover.size()) {
        cover[ib] += (xb - static_cast<double>(ib)) * w;
    }
}

void RasterCanvas::fill(const PixelRings& rings, Rgba c)
{
    const std::vector<Edge> edges = downward_edges(rings);
    if (edges.empty()) {
        return;
    }
    const Box bounds = edge_bounds(edges);
    const int col0 = static_cast<int>(std::max(m_clip.xmin, std::floor(bounds.xmin)));
    const int col1 = static_cast<int>(std::min(m_clip.xmax, std::ceil(bounds.xmax)));
    const int row0 = static_cast<int>(std::max(m_clip.ymin, std::floor(bounds.ymin)));
    const int row1 = static_cast<int>(std::min(m_clip.ymax, std::ceil(bounds.ymax)));
    std::vector<double> cover(static_cast<std::size_t>(m_width) + 1, 0.0), xs;
    std::vector<const Edge*> active;
    std::size_t next = 0;
    for (int row = row0; row < row1; ++row) {
        if (col1 <= col0) {
            break;
        }
        std::fill(cover.begin() + col0, cover.begin() + col1 + 1, 0.0);
        for (int sub = 0; sub < k_sub; ++sub) {
            const double y = row + (sub + 0.5) / k_sub;
            while (next < edges.size() && edges[next].y0 <= y) {
                active.push_back(&edges[next++]);
            }
            std::erase_if(active, [y](const Edge* e) { return e->y1 <= y; });
            xs.clear();
            for (const Edge* e : active) {
                if (e->y0 <= y) {
                    xs.push_back(e->x0 + (y - e->y0) / (e->y1 - e->y0) * (e->x1 - e->x0));
                }
            }
            std::sort(xs.begin(), xs.end());
            for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
                add_span(cover, xs[i], xs[i + 1]);
            }
        }
        for (int x = col0; x < col1; ++x) {
            blend(x, row, c, std::min(1.0, cover[static_cast<std::size_t>(x)]));
        }
    }
}

/// GDAL's last message without the line break some drivers end it with.
std::string gdal_message(const ScopedErrorCapture& capture, const std::string& fallback)
{
    std::string message = capture.last_error(fallback);
    while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) {
        message.pop_back();
    }
    return message;
}

// PNG through GDAL into memory (/vsimem/): the file itself is written by the caller, atomically.
std::string RasterCanvas::encode(const std::string& path)
{
    ScopedErrorCapture capture;
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
    if (!mem || !png) {
        throw io_error(path, "", "GDAL has no MEM or PNG driver");
    }
    GDALDatasetUniquePtr image(mem->Create("", m_width, m_height, 3, GDT_Byte, nullptr));
    if (!image) {
        throw io_error(path, "", gdal_message(capture, "cannot create an image in memory"));
    }
    const CPLErr err = image->RasterIO(GF_Write, 0, 0, m_width, m_height, m_pixels.data(), m_width, m_height, GDT_Byte, 3,
                                       nullptr, 3, static_cast<GSpacing>(m_width) * 3, 1, nullptr);
    if (err != CE_None) {
        throw io_error(path, "", gdal_message(capture, "cannot fill the image"));
    }
    const std::string memory = "/vsimem/trisnap_render_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)) + ".png";
    GDALDatasetUniquePtr written(png->CreateCopy(memory.c_str(), image.get(), FALSE, nullptr, nullptr, nullptr));
    if (!written) {
        VSIUnlink(memory.c_str());
        throw io_error(path, "", gdal_message(capture, "cannot encode the PNG"));
    }
    written.reset(); // the PNG is complete once its dataset is closed
    vsi_l_offset size = 0;
    GByte* data = VSIGetMemFileBuffer(memory.c_str(), &size, TRUE); // takes the buffer, removes the file
    std::string bytes(reinterpret_cast<const char*>(data), static_cast<std::size_t>(size));
    CPLFree(data);
    return bytes;
}

} // namespace

std::unique_ptr<Canvas> make_png_canvas(int width, int height, Rgba background)
{
    return std::make_unique<RasterCanvas>(width, height, background);
}

} // namespace trisnap::render
