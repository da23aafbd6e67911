#pragma once
// Plain geometry for drawing and measuring: points, boxes, and one feature as rings. Kept apart
// from src/core on purpose: `render` judges the engine's output and must not share its code.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace trisnap::render {

struct XY {
    double x = 0;
    double y = 0;
    friend bool operator==(const XY&, const XY&) = default;
    friend auto operator<=>(const XY&, const XY&) = default;
};

/// Axis-aligned box; a default box is empty and grows with add().
struct Box {
    double xmin = std::numeric_limits<double>::infinity();
    double ymin = std::numeric_limits<double>::infinity();
    double xmax = -std::numeric_limits<double>::infinity();
    double ymax = -std::numeric_limits<double>::infinity();

    bool empty() const { return !(xmin <= xmax && ymin <= ymax); }
    double width() const { return xmax - xmin; }
    double height() const { return ymax - ymin; }
    XY centre() const { return {(xmin + xmax) / 2, (ymin + ymax) / 2}; }
    void add(XY p);
    void add(const Box& b);
    bool intersects(const Box& b) const;
    bool contains(XY p) const { return p.x >= xmin && p.x <= xmax && p.y >= ymin && p.y <= ymax; }
    /// The box grown by `d` on every side.
    Box grown(double d) const { return {xmin - d, ymin - d, xmax + d, ymax + d}; }
    static Box around(XY c, double half) { return {c.x - half, c.y - half, c.x + half, c.y + half}; }
};

/// One feature: polygon rings (closed, last point == first) or lines (open), in layer units.
/// `identity` is a hash of the key that matches input and output features (FID, `orig_fid` or
/// --key, as assess matches them), so a feature and its snapped self get the same colour.
struct Shape {
    std::int64_t fid = -1;
    std::uint32_t identity = 0;
    bool polygon = true;
    std::vector<std::vector<XY>> rings;
    Box box;
};

/// What the scale bar needs to know about the CRS.
struct CrsInfo {
    enum class Kind { none, geographic, projected } kind = Kind::none;
    double metres_per_unit = 0; ///< projected: the linear unit; geographic: computed per view
    std::string unit = "units"; ///< "deg", "m", "ft", ...
};

struct Layer {
    std::string path;
    std::string name;
    std::vector<Shape> shapes; ///< in layer order
    CrsInfo crs;
    Box extent; ///< of the shapes read
};

double distance(XY a, XY b);
/// Distance from p to segment ab (the PNG rasteriser's antialiasing); `nearest` receives the
/// closest point on ab.
double distance_to_segment(XY p, XY a, XY b, XY* nearest = nullptr);

} // namespace trisnap::render
