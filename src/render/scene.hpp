#pragma once
// Drawing layers, sites, a scale bar and a legend onto a Canvas through a View (world box to
// pixel box). Features are clipped to the view and vertices closer than a third of a pixel
// to the previous one are dropped while drawing; nothing else is simplified.
#include "render/canvas.hpp"
#include "render/sites.hpp"

namespace trisnap::render {

/// World box to pixel box with one scale for both axes, centred, y flipped. On a geographic
/// CRS x is drawn shrunk by `x_stretch` = cos(latitude) so shapes keep their proportions.
class View {
public:
    View(const Box& world, const Box& px, double x_stretch);
    XY to_px(XY p) const { return {m_origin.x + (p.x - m_world.xmin) * m_sx, m_origin.y - (p.y - m_world.ymin) * m_sy}; }
    const Box& world() const { return m_world; } ///< what is shown (at least the box asked for)
    const Box& px() const { return m_px; }
    double px_per_unit_x() const { return m_sx; }

private:
    Box m_world;
    Box m_px;
    XY m_origin; // pixel of (world.xmin, world.ymin)
    double m_sx = 1, m_sy = 1;
};

/// cos(latitude of the box centre) for geographic layers whose box is less than 60° tall, else 1.
double x_stretch_for(const CrsInfo& crs, const Box& world);

/// input_thin: orange lines; output_bold: blue outline, light fill; output_identity: blue
/// outline, each feature filled with its identity colour (panels: who holds which area);
/// only_layer: IN drawn alone.
enum class LayerRole { input_thin, output_bold, output_identity, only_layer };

/// Draws the shapes of `layer` meeting the view; returns how many were drawn. `overview`
/// draws thinner lines (features are a few pixels wide there).
std::size_t draw_layer(Canvas& canvas, const View& view, const Layer& layer, LayerRole role, bool overview);

Rgba kind_colour(SiteKind kind);
/// "site-collapse", "site-drift", ...: the SVG class of a site's marker.
const char* site_class(SiteKind kind);

/// FNV-1a of a feature's matching key: the same identity for a feature and its snapped self.
std::uint32_t identity_of(const std::string& key);

/// A light colour from a feature's identity (a hash of its matching key), the same for a
/// feature and its snapped self, different for neighbours with near certainty.
Rgba identity_colour(std::uint32_t identity);

/// A small fixed-size circle (overview): thick for contract breaches.
void draw_site_marker(Canvas& canvas, const View& view, const Site& site);
/// The rank and code of a worst site beside its marker ("#1 drift"; rank 0: the code alone), on
/// a white ground, on the first side of the marker where it covers no label in `placed` (then
/// added to it).
void draw_site_label(Canvas& canvas, const View& view, const Site& site, std::size_t rank, std::vector<Box>& placed);
/// A panel's site: the pair joined by a line, circled with room to spare.
void draw_site_focus(Canvas& canvas, const View& view, const Site& site);

/// A bar of a round length (metres when the CRS says how) at the view's lower left.
void draw_scale_bar(Canvas& canvas, const View& view, const CrsInfo& crs);

/// One row of legend entries starting at `at`: input, output, then the site kinds present.
/// `identity`: the output is filled by identity (say so instead of showing one fill).
void draw_legend(Canvas& canvas, XY at, bool two_layers, bool identity, const std::vector<SiteKind>& kinds);

/// The length in metres of `units` layer units at latitude `lat` (0 when unknown).
double metres(const CrsInfo& crs, double units, double lat);

} // namespace trisnap::render
