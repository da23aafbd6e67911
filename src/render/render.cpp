#include "render/render.hpp"

#include "config/errors.hpp"
#include "io/io_error.hpp"
#include "render/canvas.hpp"
#include "render/layer_reader.hpp"
#include "render/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace trisnap::render {
namespace {

const Rgba k_background{255, 255, 255};
const Rgba k_text{30, 30, 30};
constexpr int k_margin = 10;
constexpr int k_header = 44;      // two lines of text above the map or panels
constexpr int k_footer = 30;      // the legend
constexpr int k_panel_title = 30; // two lines above each panel
constexpr std::size_t k_max_markers_per_kind = 500;
constexpr std::size_t k_top_per_kind = 3; // marked even when within the contract

struct Inputs {
    Layer in;
    std::optional<Layer> out;
    std::vector<Site> problems;
    std::optional<double> tolerance;
};

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

Inputs read_inputs(const RenderOptions& o)
{
    Inputs inputs;
    inputs.tolerance = o.tolerance;
    std::optional<double> report_tolerance;
    if (!o.problems_report.empty()) inputs.problems = read_problem_sites(o.problems_report, report_tolerance);
    if (!inputs.tolerance) inputs.tolerance = report_tolerance;
    if (o.worst > 0 && !inputs.tolerance)
        throw argument_error("--worst needs --tolerance T (or a --problems report that records it): sites are ranked in multiples of T");
    inputs.in = read_layer(o.input, o.layer_a, o.bbox, o.key);
    if (!o.snapped.empty()) inputs.out = read_layer(o.snapped, o.layer_b, o.bbox, o.key);
    if (inputs.in.shapes.empty() && (!inputs.out || inputs.out->shapes.empty()))
        throw io_error(o.input, inputs.in.name, o.bbox ? "no feature in --bbox: nothing to draw" : "no polygons or lines to draw");
    if (o.bbox)
        std::erase_if(inputs.problems, [&](const Site& s) { return !o.bbox->contains(s.at); });
    return inputs;
}

std::string times_t(double value, std::optional<double> t)
{
    if (!t) return fmt::format("{:.3g}", value);
    const double m = value / *t;
    return m >= 100 ? fmt::format("{:.0f} T", m) : fmt::format("{:.2f} T", m);
}

std::string site_title(const Site& s, std::optional<double> t)
{
    switch (s.kind) {
    case SiteKind::collapse: return "collapse: lost, " + s.name + " " + times_t(s.value, t);
    case SiteKind::drift: return "drift " + times_t(s.value, t) + (s.defect ? " (> 2T)" : "");
    case SiteKind::vertex_edge: return "vertex-edge " + times_t(s.value, t) + (s.defect ? " (< T/2)" : "");
    case SiteKind::vertex_vertex: return "vertex-vertex " + times_t(s.value, t) + (s.defect ? " (< T)" : "");
    case SiteKind::problem: return fmt::format("problem {} {}", s.code, s.name);
    }
    return "";
}

std::string site_detail(const Site& s)
{
    std::string fids = fmt::format("fid {}", s.fid);
    if (s.fid2 >= 0 && s.fid2 != s.fid) fids += fmt::format(" / {}", s.fid2);
    return fmt::format("{} at {:.10g}, {:.10g}", fids, s.at.x, s.at.y);
}

XY site_centre(const Site& s)
{
    if (s.kind == SiteKind::collapse && !s.extent.empty()) return s.extent.centre();
    return {(s.at.x + s.other.x) / 2, (s.at.y + s.other.y) / 2};
}

std::vector<SiteKind> kinds_present(const std::vector<Site>& sites)
{
    std::vector<SiteKind> kinds;
    for (const Site& s : sites)
        if (std::find(kinds.begin(), kinds.end(), s.kind) == kinds.end()) kinds.push_back(s.kind);
    std::sort(kinds.begin(), kinds.end());
    return kinds;
}

/// Overview markers: every breach (up to a cap per kind) and the few worst of each kind.
std::vector<Site> marked_sites(const std::vector<Site>& sites)
{
    std::vector<Site> marked;
    std::vector<std::size_t> breaches(k_site_kinds, 0), others(k_site_kinds, 0);
    for (const Site& s : sites) {
        const auto k = static_cast<std::size_t>(s.kind);
        if (s.defect ? breaches[k]++ < k_max_markers_per_kind : others[k]++ < k_top_per_kind) marked.push_back(s);
    }
    return marked;
}

std::string tolerance_text(const Inputs& in)
{
    if (!in.tolerance) return "no tolerance given";
    const Box& e = in.in.extent.empty() ? in.out->extent : in.in.extent;
    const double m = metres(in.in.crs, *in.tolerance, e.centre().y);
    std::string text = fmt::format("T = {:.6g} {}", *in.tolerance, in.in.crs.unit);
    if (m > 0 && in.in.crs.unit != "m") text += fmt::format(" ({:.3g} m)", m);
    return text;
}

void draw_header(Canvas& canvas, const RenderOptions& o, const Inputs& in, const std::string& what)
{
    std::string title = "trisnap render: " + file_name(o.input) + " (" + in.in.name + ")";
    if (in.out) title += " -> " + file_name(o.snapped) + " (" + in.out->name + ")";
    canvas.text({k_margin, 16}, title, 1, k_text, Anchor::start);
    std::string line = tolerance_text(in) + fmt::format("   {} features in", in.in.shapes.size());
    if (in.out) line += fmt::format(", {} out", in.out->shapes.size());
    canvas.text({k_margin, 32}, line + "   " + what, 1, k_text, Anchor::start);
}

/// Panels draw the input over the output (both visible where they coincide); the overview
/// draws it underneath, so at that scale it shows only where the output moved or vanished.
void draw_map(Canvas& canvas, const View& view, const Inputs& in, bool overview)
{
    canvas.begin_clip(view.px());
    if (!in.out) {
        draw_layer(canvas, view, in.in, LayerRole::only_layer, overview);
    } else if (overview) {
        draw_layer(canvas, view, in.in, LayerRole::input_thin, overview);
        draw_layer(canvas, view, *in.out, LayerRole::output_bold, overview);
    } else {
        draw_layer(canvas, view, *in.out, LayerRole::output_bold, overview);
        draw_layer(canvas, view, in.in, LayerRole::input_thin, overview);
    }
}

void finish_map(Canvas& canvas, const View& view, const CrsInfo& crs)
{
    canvas.end_clip();
    canvas.rect(view.px(), {std::nullopt, Rgba{120, 120, 120}, 1}, "frame");
    draw_scale_bar(canvas, view, crs);
}

std::unique_ptr<Canvas> make_canvas(const std::string& path, int width, int height)
{
    bool png = false;
    picture_format(path, png);
    return png ? make_png_canvas(width, height, k_background) : make_svg_canvas(width, height, k_background);
}

void render_overview(const RenderOptions& o, const Inputs& in, RenderResult& result)
{
    Box world = o.bbox ? *o.bbox : in.in.extent;
    if (!o.bbox && in.out) world.add(in.out->extent);
    world = world.grown(std::max({world.width(), world.height(), 1e-9}) * 0.02);
    const double stretch = x_stretch_for(in.in.crs, world);
    const int map_w = o.width - 2 * k_margin;
    const double aspect = world.height() / (world.width() * stretch);
    const int map_h = static_cast<int>(std::lround(std::clamp(map_w * aspect, 0.3 * map_w, 1.25 * map_w)));
    result.width = o.width;
    result.height = k_header + map_h + k_footer + k_margin;
    auto canvas = make_canvas(o.output, result.width, result.height);
    result.shown = marked_sites(result.sites);
    draw_header(*canvas, o, in, fmt::format("{} sites marked", result.shown.size()));
    const View view(world, Box{k_margin, k_header, k_margin + static_cast<double>(map_w), k_header + static_cast<double>(map_h)}, stretch);
    draw_map(*canvas, view, in, true);
    for (const Site& s : result.shown) draw_site_marker(*canvas, view, s);
    finish_map(*canvas, view, in.in.crs);
    draw_legend(*canvas, {k_margin, static_cast<double>(result.height - k_footer / 2 - 2)}, in.out.has_value(),
                kinds_present(result.shown));
    canvas->save(o.output);
}

void render_panels(const RenderOptions& o, const Inputs& in, RenderResult& result)
{
    const double t = *in.tolerance;
    result.shown = pick_worst(result.sites, static_cast<std::size_t>(o.worst), 3 * t);
    const auto n = static_cast<int>(result.shown.size());
    const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    const int rows = (n + cols - 1) / cols;
    const int side = (o.width - k_margin * (cols + 1)) / cols;
    result.width = o.width;
    result.height = k_header + rows * (k_panel_title + side + k_margin) + k_footer;
    result.panels = result.shown.size();
    auto canvas = make_canvas(o.output, result.width, result.height);
    draw_header(*canvas, o, in, fmt::format("the {} worst sites", n));
    for (int i = 0; i < n; ++i) {
        const Site& s = result.shown[static_cast<std::size_t>(i)];
        const double x0 = k_margin + (i % cols) * (side + k_margin);
        const double y0 = k_header + (i / cols) * (k_panel_title + side + k_margin);
        canvas->text({x0, y0 + 11}, fmt::format("#{} {}", i + 1, site_title(s, in.tolerance)), 1, kind_colour(s.kind), Anchor::start);
        canvas->text({x0, y0 + 24}, site_detail(s), 1, k_text, Anchor::start);
        const Box world = Box::around(site_centre(s), panel_half_size(s, t));
        const View view(world, Box{x0, y0 + k_panel_title, x0 + side, y0 + k_panel_title + side}, x_stretch_for(in.in.crs, world));
        draw_map(*canvas, view, in, false);
        draw_site_focus(*canvas, view, s);
        finish_map(*canvas, view, in.in.crs);
    }
    draw_legend(*canvas, {k_margin, static_cast<double>(result.height - k_footer / 2 - 2)}, in.out.has_value(),
                kinds_present(result.shown));
    canvas->save(o.output);
}

} // namespace

bool picture_format(const std::string& path, bool& png)
{
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    png = ext == ".png";
    return png || ext == ".svg";
}

void check_options(const RenderOptions& o)
{
    bool png = false;
    if (!picture_format(o.output, png))
        throw argument_error("-o " + o.output + ": cannot tell the picture format; use a name ending in .svg or .png");
    if (o.width < 200 || o.width > 20000) throw argument_error(fmt::format("--width must be 200..20000 pixels, got {}", o.width));
    if (o.worst < 0 || o.worst > 100) throw argument_error(fmt::format("--worst must be 1..100, got {}", o.worst));
    if (o.tolerance && !(std::isfinite(*o.tolerance) && *o.tolerance > 0))
        throw argument_error(fmt::format("--tolerance must be finite and > 0, got {}", *o.tolerance));
}

RenderResult render(const RenderOptions& options)
{
    check_options(options);
    const std::filesystem::path folder = std::filesystem::absolute(options.output).parent_path();
    if (!std::filesystem::is_directory(folder))
        throw io_error(options.output, "", "cannot write there: no directory " + folder.string());
    const Inputs inputs = read_inputs(options);
    RenderResult result;
    result.tolerance = inputs.tolerance;
    result.features_in = inputs.in.shapes.size();
    result.features_out = inputs.out ? inputs.out->shapes.size() : 0;
    result.sites = find_sites(inputs.in, inputs.out ? &*inputs.out : nullptr, inputs.tolerance, inputs.problems);
    if (options.worst > 0 && !result.sites.empty()) render_panels(options, inputs, result);
    else render_overview(options, inputs, result);
    return result;
}

std::string summarise(const RenderResult& r)
{
    std::string out;
    for (int k = 0; k < k_site_kinds; ++k) {
        std::size_t count = 0, breaches = 0;
        const Site* first = nullptr;
        for (const Site& s : r.sites)
            if (static_cast<int>(s.kind) == k) count++, breaches += s.defect, first = first ? first : &s;
        if (!first) continue;
        const auto kind = static_cast<SiteKind>(k);
        out += fmt::format("  {:<14} {:>7} found", kind_name(kind), count);
        if (kind == SiteKind::drift || kind == SiteKind::vertex_edge || kind == SiteKind::vertex_vertex)
            out += fmt::format(", {} breach the contract, worst {} (fid {})", breaches, times_t(first->value, r.tolerance), first->fid);
        out += "\n";
    }
    return out.empty() ? "  no sites found\n" : out;
}

} // namespace trisnap::render
