#include "render/scene.hpp"

#include "io/tolerance.hpp"
#include "render/clip.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace trisnap::render {
namespace {

constexpr double k_min_step_px = 0.35; // vertices closer than this to the last one are not drawn
constexpr double k_clip_margin_px = 4; // clip edges fall outside the visible area (and strokes)

const Rgba k_ink{30, 30, 30};
const Rgba k_white{255, 255, 255};

/// Zoomed panels: bold output under a thin input. Overview: both thinner (features are a few
/// pixels wide there) and the input underneath, so it shows only where the output left it.
Style role_style(LayerRole role, bool overview = false)
{
    switch (role) {
    case LayerRole::input_thin: return {std::nullopt, Rgba{235, 110, 20}, 1.0};
    case LayerRole::output_bold: return {Rgba{110, 160, 215, 110}, Rgba{25, 55, 120}, overview ? 1.0 : 2.2};
    case LayerRole::output_identity: return {std::nullopt, Rgba{25, 55, 120}, 2.2};
    case LayerRole::only_layer: return {Rgba{110, 160, 215, 110}, Rgba{25, 55, 120}, 0.8};
    }
    return {};
}

const char* role_class(LayerRole role)
{
    const bool output = role == LayerRole::output_bold || role == LayerRole::output_identity;
    return output ? "out" : "in";
}

/// A shape's style: lines are never filled; identity fills come from the shape.
Style shape_style(const Shape& shape, LayerRole role, const Style& style)
{
    if (!shape.polygon) {
        return {std::nullopt, style.stroke, style.width};
    }
    if (role == LayerRole::output_identity) {
        return {identity_colour(shape.identity), style.stroke, style.width};
    }
    return style;
}

PixelRings shape_to_px(const Shape& shape, const View& view, bool clip)
{
    const Box limit = view.px().grown(k_clip_margin_px);
    PixelRings rings;
    for (const auto& ring : shape.rings) {
        std::vector<XY> px;
        px.reserve(ring.size());
        for (XY p : ring) {
            px.push_back(view.to_px(p));
        }
        px = drop_close_points(px, k_min_step_px);
        if (!clip) {
            rings.push_back(std::move(px));
        } else if (shape.polygon) {
            if (auto clipped = clip_ring(px, limit); !clipped.empty()) {
                rings.push_back(std::move(clipped));
            }
        } else {
            for (auto& piece : clip_line(px, limit)) {
                rings.push_back(std::move(piece));
            }
        }
    }
    return rings;
}

/// 1, 2 or 5 times a power of ten, the largest not above `v`.
double round_down_nice(double v)
{
    const double p = std::pow(10.0, std::floor(std::log10(v)));
    for (double m : {5.0, 2.0, 1.0}) {
        if (m * p <= v) {
            return m * p;
        }
    }
    return p;
}

std::string short_number(double v) { return fmt::format("{:.3g}", v); }

/// A round length in metres as text: "200 m", "5 km", "0.05 m".
std::string metres_text(double m) { return m >= 1000 ? fmt::format("{:g} km", m / 1000) : fmt::format("{:g} m", m); }

} // namespace

View::View(const Box& world, const Box& px, double x_stretch) : m_px(px)
{
    const double w = std::max(world.width(), 1e-300), h = std::max(world.height(), 1e-300);
    const double scale = std::min(px.width() / (w * x_stretch), px.height() / h);
    m_sx = scale * x_stretch;
    m_sy = scale;
    const XY c = world.centre();
    const double half_w = px.width() / m_sx / 2, half_h = px.height() / m_sy / 2;
    m_world = {c.x - half_w, c.y - half_h, c.x + half_w, c.y + half_h};
    m_origin = {px.xmin, px.ymax};
}

double x_stretch_for(const CrsInfo& crs, const Box& world)
{
    // Coordinates beyond ±90 in y are not latitudes, whatever the CRS says.
    if (crs.kind != CrsInfo::Kind::geographic || world.height() > 60 || world.ymin < -90 || world.ymax > 90) {
        return 1.0;
    }
    const double lat = std::clamp(world.centre().y, -80.0, 80.0);
    return std::cos(lat * std::numbers::pi / 180.0);
}

double metres(const CrsInfo& crs, double units, double lat)
{
    if (crs.kind == CrsInfo::Kind::geographic) {
        return std::abs(lat) <= 90 ? units * metres_per_degree(lat) : 0.0; // as --tolerance-m converts
    }
    if (crs.kind == CrsInfo::Kind::projected) {
        return units * crs.metres_per_unit;
    }
    return 0;
}

std::size_t draw_layer(Canvas& canvas, const View& view, const Layer& layer, LayerRole role, bool overview)
{
    const Box shown = view.world();
    const Style style = role_style(role, overview);
    std::size_t drawn = 0;
    for (const Shape& shape : layer.shapes) {
        if (!shape.box.intersects(shown)) {
            continue;
        }
        const bool inside = shape.box.xmin >= shown.xmin && shape.box.xmax <= shown.xmax &&
                            shape.box.ymin >= shown.ymin && shape.box.ymax <= shown.ymax;
        PixelRings rings = shape_to_px(shape, view, !inside);
        if (rings.empty()) {
            continue;
        }
        canvas.path(rings, shape.polygon, shape_style(shape, role, style), role_class(role));
        ++drawn;
    }
    return drawn;
}

Rgba kind_colour(SiteKind kind)
{
    switch (kind) {
    case SiteKind::missing: return {210, 0, 150};
    case SiteKind::invalid: return {120, 0, 0};
    case SiteKind::crossing: return {230, 120, 0};
    case SiteKind::overlap: return {160, 90, 0};
    case SiteKind::gap: return {0, 90, 220};
    case SiteKind::drift: return {220, 0, 0};
    case SiteKind::vertex_edge: return {130, 40, 200};
    case SiteKind::vertex_vertex: return {0, 150, 150};
    case SiteKind::problem: return {40, 150, 0};
    }
    return k_ink;
}

const char* site_class(SiteKind kind)
{
    switch (kind) {
    case SiteKind::missing: return "site-missing";
    case SiteKind::invalid: return "site-invalid";
    case SiteKind::crossing: return "site-crossing";
    case SiteKind::overlap: return "site-overlap";
    case SiteKind::gap: return "site-gap";
    case SiteKind::drift: return "site-drift";
    case SiteKind::vertex_edge: return "site-vertex-edge";
    case SiteKind::vertex_vertex: return "site-vertex-vertex";
    case SiteKind::problem: return "site-problem";
    }
    return "site";
}

std::uint32_t identity_of(const std::string& key)
{
    std::uint32_t h = 2166136261u;
    for (unsigned char c : key) {
        h = (h ^ c) * 16777619u;
    }
    // MurmurHash3's finaliser: keys differing in one character land far apart in hue.
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

Rgba identity_colour(std::uint32_t identity)
{
    // Hue from the hash, and one of three lightnesses, pale enough for the outlines and the
    // input on top to stay readable.
    const double h = static_cast<double>(identity % 360u) / 60.0;
    const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
    const std::array<std::array<double, 3>, 6> sextant{{{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}}};
    const auto& c = sextant[static_cast<std::size_t>(h) % 6];
    const double base = 0.55 + 0.07 * static_cast<double>((identity >> 16) % 3);
    const auto channel = [&](double v) { return static_cast<std::uint8_t>(std::lround(255 * (base + (0.97 - base) * v))); };
    return {channel(c[0]), channel(c[1]), channel(c[2]), 170};
}

void draw_site_marker(Canvas& canvas, const View& view, const Site& site)
{
    const Style style{std::nullopt, kind_colour(site.kind), site.breach ? 2.0 : 1.2};
    canvas.circle(view.to_px(xy(site.at)), site.kind == SiteKind::problem ? 5 : 7, style, site_class(site.kind));
}

void draw_site_label(Canvas& canvas, const View& view, const Site& site, std::size_t rank, std::vector<Box>& placed)
{
    const XY at = view.to_px(xy(site.at));
    const std::string code = assess::site_code(site);
    const std::string label = rank > 0 ? fmt::format("#{} {}", rank, code) : code;
    const double width = Canvas::text_width(label, 1) + 2;
    // Right of the marker, then below, above and left; a ranked site's label goes right when
    // every side is taken, a code alone is left out then.
    const std::array<XY, 4> corners{{{at.x + 8, at.y - 6}, {at.x + 8, at.y + 5}, {at.x + 8, at.y - 17}, {at.x - 8 - width, at.y - 6}}};
    std::optional<Box> box;
    for (XY c : corners) {
        const Box candidate{c.x, c.y, c.x + width, c.y + 10};
        if (!box && std::none_of(placed.begin(), placed.end(), [&](const Box& b) { return b.intersects(candidate); })) {
            box = candidate;
        }
    }
    if (!box && rank == 0) {
        return;
    }
    if (!box) {
        box = Box{corners[0].x, corners[0].y, corners[0].x + width, corners[0].y + 10};
    }
    placed.push_back(*box);
    canvas.rect(*box, {Rgba{255, 255, 255, 220}, std::nullopt, 1}, "label");
    canvas.text({box->xmin + 1, box->ymax - 1}, label, 1, kind_colour(site.kind), Anchor::start);
}

void draw_site_focus(Canvas& canvas, const View& view, const Site& site)
{
    const Rgba colour = kind_colour(site.kind);
    const XY a = view.to_px(xy(site.at));
    const XY b = view.to_px(xy(site.other));
    double radius = distance(a, b) / 2 + 10;
    XY centre{(a.x + b.x) / 2, (a.y + b.y) / 2};
    if (site.kind == SiteKind::missing && !site.extent.empty()) {
        const XY lo = view.to_px({site.extent.xmin, site.extent.ymin});
        const XY hi = view.to_px({site.extent.xmax, site.extent.ymax});
        radius = std::max(radius, distance(lo, hi) / 2 + 8);
        centre = {(lo.x + hi.x) / 2, (lo.y + hi.y) / 2};
    }
    if (!(a == b)) {
        canvas.path({{a, b}}, false, {std::nullopt, colour, 1.5}, "link");
        canvas.circle(b, 2.5, {colour, std::nullopt, 1}, "link");
    }
    canvas.circle(a, 3, {colour, std::nullopt, 1}, "link");
    canvas.circle(centre, radius, {std::nullopt, colour, 2.0}, site_class(site.kind));
}

void draw_scale_bar(Canvas& canvas, const View& view, const CrsInfo& crs)
{
    const double lat = view.world().centre().y;
    const double max_units = view.px().width() / 4 / view.px_per_unit_x();
    const double m_per_unit = metres(crs, 1.0, lat);
    double units = round_down_nice(max_units);
    std::string label = crs.unit == "m" ? metres_text(units) : fmt::format("{:g} {}", units, crs.unit);
    if (m_per_unit > 0 && crs.unit != "m") {
        const double m = round_down_nice(max_units * m_per_unit);
        units = m / m_per_unit;
        label = metres_text(m) + " (" + short_number(units) + " " + crs.unit + ")";
    }
    const double length = units * view.px_per_unit_x();
    const XY at{view.px().xmin + 10, view.px().ymax - 10};
    const double half = std::round(length / 2);
    canvas.rect({at.x - 1, at.y - 5, at.x + length + 1, at.y + 1}, {k_white, std::nullopt, 1}, "scale");
    canvas.rect({at.x, at.y - 4, at.x + half, at.y}, {k_ink, std::nullopt, 1}, "scale");
    canvas.rect({at.x + half, at.y - 4, at.x + length, at.y}, {k_white, k_ink, 1}, "scale");
    canvas.rect({at.x - 1, at.y - 17, at.x + Canvas::text_width(label, 1) + 1, at.y - 7}, {Rgba{255, 255, 255, 200}, std::nullopt, 1}, "scale");
    canvas.text({at.x, at.y - 8}, label, 1, k_ink, Anchor::start);
}

void draw_legend(Canvas& canvas, XY at, bool two_layers, bool identity, const std::vector<SiteKind>& kinds)
{
    double x = at.x;
    const double y = at.y;
    auto label = [&](const std::string& text) {
        canvas.text({x, y + 4}, text, 1, k_ink, Anchor::start);
        x += Canvas::text_width(text, 1) + 16;
    };
    Style first = role_style(two_layers ? LayerRole::output_bold : LayerRole::only_layer);
    if (identity) {
        first.fill = identity_colour(7);
    }
    canvas.path({{{x, y - 5}, {x + 22, y - 5}, {x + 22, y + 5}, {x, y + 5}}}, true, first, "legend");
    x += 28;
    label(two_layers ? (identity ? "output (fill: one colour per feature)" : "output (snapped)") : "input");
    if (two_layers) {
        canvas.path({{{x, y}, {x + 22, y}}}, false, role_style(LayerRole::input_thin), "legend");
        x += 28;
        label("input");
    }
    for (SiteKind kind : kinds) {
        canvas.circle({x + 7, y}, 6, {std::nullopt, kind_colour(kind), 2}, "legend");
        x += 18;
        label(assess::site_kind_name(kind));
    }
}

} // namespace trisnap::render
