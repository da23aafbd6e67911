#include "render/render.hpp"

#include "config/errors.hpp"
#include "io/commit_group.hpp"
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
constexpr int k_panel_title = 43; // three lines above each panel
constexpr std::size_t k_max_markers_per_kind = 500;
constexpr std::size_t k_ranked_in_overview = 10;
constexpr std::size_t k_max_code_labels = 60; // more markers than this get no code beside them

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

AssessReport measure(const Inputs& in, const RenderOptions& o)
{
    const std::size_t ranked = o.worst > 0 ? static_cast<std::size_t>(o.worst) : k_ranked_in_overview;
    AssessOptions options{*in.tolerance, o.key, k_max_markers_per_kind, ranked};
    options.report = in.report ? &*in.report : nullptr;
    return assess_data(in.data.a, in.data.b, in.data.matched_by, options);
}

std::vector<SiteKind> kinds_present(const std::vector<Site>& sites)
{
    std::vector<SiteKind> kinds;
    for (const Site& s : sites) {
        if (std::find(kinds.begin(), kinds.end(), s.kind) == kinds.end()) {
            kinds.push_back(s.kind);
        }
    }
    std::sort(kinds.begin(), kinds.end());
    return kinds;
}

/// Overview markers: every breach (up to a cap per kind), every reported problem, and the
/// ranked sites even when within the contract.
std::vector<Site> marked_sites(const std::vector<Site>& sites, const std::vector<Site>& ranked)
{
    std::vector<Site> marked;
    std::vector<std::size_t> per_kind(k_site_kinds, 0);
    for (const Site& s : sites) {
        const bool wanted = s.breach || s.kind == SiteKind::problem;
        if (wanted && per_kind[static_cast<std::size_t>(s.kind)]++ < k_max_markers_per_kind) {
            marked.push_back(s);
        }
    }
    for (const Site& s : ranked) {
        if (!s.breach && s.kind != SiteKind::problem) {
            marked.push_back(s);
        }
    }
    return marked;
}

std::string tolerance_text(const Inputs& in)
{
    if (!in.tolerance) {
        return "no tolerance given";
    }
    const Box& e = in.in.extent.empty() ? in.out->extent : in.in.extent;
    const double m = metres(in.in.crs, *in.tolerance, e.centre().y);
    std::string text = fmt::format("T = {:.6g} {}", *in.tolerance, in.in.crs.unit);
    if (m > 0 && in.in.crs.unit != "m") {
        text += fmt::format(" ({:.3g} m)", m);
    }
    return text;
}

void draw_header(Canvas& canvas, const RenderOptions& o, const Inputs& in, const std::string& what)
{
    std::string title = "trisnap render: " + file_name(o.input) + " (" + in.in.name + ")";
    if (in.out) {
        title += " -> " + file_name(o.snapped) + " (" + in.out->name + ")";
    }
    canvas.text({k_margin, 16}, title, 1, k_text, Anchor::start);
    std::string line = tolerance_text(in) + fmt::format("   {} features in", in.in.shapes.size());
    if (in.out) {
        line += fmt::format(", {} out", in.out->shapes.size());
    }
    canvas.text({k_margin, 32}, line + "   " + what, 1, k_text, Anchor::start);
}

/// The output underneath, the thin input on top: where they coincide both show, where the
/// output moved or vanished the input stands alone. Panels fill the output by identity.
void draw_map(Canvas& canvas, const View& view, const Inputs& in, bool overview)
{
    canvas.begin_clip(view.px());
    if (!in.out) {
        draw_layer(canvas, view, in.in, LayerRole::only_layer, overview);
        return;
    }
    draw_layer(canvas, view, *in.out, overview ? LayerRole::output_bold : LayerRole::output_identity, overview);
    draw_layer(canvas, view, in.in, LayerRole::input_thin, overview);
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

void draw_legend_row(Canvas& canvas, const RenderResult& result, const Inputs& in, bool identity)
{
    draw_legend(canvas, {k_margin, static_cast<double>(result.height - k_footer / 2 - 2)}, in.out.has_value(), identity,
                kinds_present(result.shown));
}

Box overview_world(const RenderOptions& o, const Inputs& in)
{
    Box world = o.bbox ? *o.bbox : in.in.extent;
    if (!o.bbox && in.out) {
        world.add(in.out->extent);
    }
    return world.grown(std::max({world.width(), world.height(), 1e-9}) * 0.02);
}

bool same_site(const Site& a, const Site& b) { return a.kind == b.kind && a.at == b.at && a.fid == b.fid && a.fid2 == b.fid2; }

/// The ranked sites get their rank and code; the other markers their code, when few enough.
void label_sites(Canvas& canvas, const View& view, const RenderResult& result)
{
    std::vector<Box> placed;
    for (std::size_t i = 0; i < result.ranked.size(); ++i) {
        draw_site_label(canvas, view, result.ranked[i], i + 1, placed);
    }
    if (result.shown.size() > k_max_code_labels) {
        return;
    }
    for (const Site& s : result.shown) {
        const bool ranked = std::any_of(result.ranked.begin(), result.ranked.end(), [&](const Site& r) { return same_site(r, s); });
        if (!ranked) {
            draw_site_label(canvas, view, s, 0, placed);
        }
    }
}

void render_overview(const RenderOptions& o, const Inputs& in, const std::vector<Site>& sites, RenderResult& result)
{
    const Box world = overview_world(o, in);
    const double stretch = x_stretch_for(in.in.crs, world);
    const int map_w = o.width - 2 * k_margin;
    const double aspect = world.height() / (world.width() * stretch);
    const int map_h = static_cast<int>(std::lround(std::clamp(map_w * aspect, 0.3 * map_w, 1.25 * map_w)));
    result.width = o.width;
    result.height = k_header + map_h + k_footer + k_margin;
    auto canvas = make_canvas(o.output, result.width, result.height);
    result.shown = marked_sites(sites, result.ranked);
    draw_header(*canvas, o, in, fmt::format("{} sites marked, the {} worst numbered", result.shown.size(), result.ranked.size()));
    const View view(world, Box{k_margin, k_header, k_margin + static_cast<double>(map_w), k_header + static_cast<double>(map_h)}, stretch);
    draw_map(*canvas, view, in, true);
    for (const Site& s : result.shown) {
        draw_site_marker(*canvas, view, s);
    }
    label_sites(*canvas, view, result);
    finish_map(*canvas, view, in.in.crs);
    draw_legend_row(*canvas, result, in, false);
    write_text_file_atomically(o.output, canvas->encode(o.output), in.protect, "-o");
}

void draw_panel_title(Canvas& canvas, XY at, const Site& s, std::size_t rank, double t)
{
    canvas.text({at.x, at.y + 11}, fmt::format("#{} {}", rank, assess::describe_site(s, t)), 1, kind_colour(s.kind), Anchor::start);
    canvas.text({at.x, at.y + 24}, assess::site_place(s), 1, k_text, Anchor::start);
    if (!s.excused_by.empty()) {
        canvas.text({at.x, at.y + 37}, "excused by " + s.excused_by, 1, k_text, Anchor::start);
    }
}

/// One panel: the site's neighbourhood, the reported problems in it, the site circled.
void draw_panel(Canvas& canvas, const Inputs& in, const std::vector<Site>& problems, const Site& s, const Box& px)
{
    const double t = *in.tolerance;
    const Box world = Box::around(site_centre(s), panel_half_size(s, t));
    const View view(world, px, x_stretch_for(in.in.crs, world));
    draw_map(canvas, view, in, false);
    for (const Site& p : problems) {
        if (view.world().contains(xy(p.at))) {
            draw_site_marker(canvas, view, p);
        }
    }
    draw_site_focus(canvas, view, s);
    finish_map(canvas, view, in.in.crs);
}

void render_panels(const RenderOptions& o, const Inputs& in, const std::vector<Site>& sites, RenderResult& result)
{
    std::vector<Site> problems;
    std::copy_if(sites.begin(), sites.end(), std::back_inserter(problems), [](const Site& s) { return s.kind == SiteKind::problem; });
    result.shown = result.ranked;
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
        draw_panel_title(*canvas, {x0, y0}, s, static_cast<std::size_t>(i) + 1, *in.tolerance);
        draw_panel(*canvas, in, problems, s, Box{x0, y0 + k_panel_title, x0 + side, y0 + k_panel_title + side});
    }
    draw_legend_row(*canvas, result, in, true);
    write_text_file_atomically(o.output, canvas->encode(o.output), in.protect, "-o");
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
    if (!picture_format(o.output, png)) {
        throw argument_error("-o " + o.output + ": cannot tell the picture format; use a name ending in .svg or .png");
    }
    if (o.width < 200 || o.width > 20000) {
        throw argument_error(fmt::format("--width must be 200..20000 pixels, got {}", o.width));
    }
    if (o.worst < 0 || o.worst > 100) {
        throw argument_error(fmt::format("--worst must be 1..100, got {}", o.worst));
    }
}

RenderResult render(const RenderOptions& options)
{
    check_options(options);
    const std::filesystem::path folder = std::filesystem::absolute(options.output).parent_path();
    if (!std::filesystem::is_directory(folder)) {
        throw io_error(options.output, "", "cannot write there: no directory " + folder.string());
    }
    const Inputs inputs = read_inputs(options);
    RenderResult result;
    result.tolerance = inputs.tolerance;
    result.features_in = inputs.in.shapes.size();
    result.features_out = inputs.out ? inputs.out->shapes.size() : 0;
    std::vector<Site> sites;
    if (inputs.tolerance) {
        result.assessment = measure(inputs, options);
        result.ranked = result.assessment->worst;
        sites = report_sites(*result.assessment);
    }
    if (options.worst > 0 && !result.ranked.empty()) {
        render_panels(options, inputs, sites, result);
    } else {
        render_overview(options, inputs, sites, result);
    }
    return result;
}

std::string summarise(const RenderResult& r)
{
    if (!r.assessment) {
        return "  no tolerance: nothing measured (give --tolerance, --tolerance-m or a --report that records it)\n";
    }
    std::string out = "  contract " + contract_verdict(*r.assessment) + "\n";
    for (const std::string& line : worst_site_lines(r.ranked, r.assessment->tolerance)) {
        out += "  " + line + "\n";
    }
    return out;
}

} // namespace trisnap::render
