#include "render/layer_reader.hpp"

#include "config/errors.hpp"
#include "io/commit_group.hpp"
#include "io/dataset.hpp"
#include "io/tolerance.hpp"
#include "render/scene.hpp"

#include <ogr_spatialref.h>

#include <stdexcept>

namespace trisnap::render {
namespace {

CrsInfo crs_info(const OGRSpatialReference* srs)
{
    CrsInfo info;
    if (!srs) {
        return info;
    }
    if (srs->IsGeographic()) {
        info.kind = CrsInfo::Kind::geographic;
        info.unit = "deg";
    } else if (srs->IsProjected()) {
        info.kind = CrsInfo::Kind::projected;
        const char* name = nullptr;
        info.metres_per_unit = srs->GetLinearUnits(&name);
        info.unit = info.metres_per_unit == 1.0 ? "m" : (name ? name : "units");
    }
    return info;
}

Shape shape_of(const assess::LayerData& d, const assess::Feature& f)
{
    Shape shape;
    shape.fid = f.fid;
    shape.identity = identity_of(f.key);
    shape.polygon = f.kind == assess::FeatureKind::polygon;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        std::vector<XY> ring;
        for (std::uint32_t k = d.parts[i].begin; k < d.parts[i].end; ++k) {
            const XY p = xy(d.pts[k]);
            if (ring.empty() || !(ring.back() == p)) {
                ring.push_back(p);
                shape.box.add(p);
            }
        }
        if (ring.size() >= 2) {
            shape.rings.push_back(std::move(ring));
        }
    }
    return shape;
}

Layer layer_of(const assess::LayerData& d, const std::string& path, const CrsInfo& crs)
{
    Layer layer;
    layer.path = path;
    layer.name = d.name;
    layer.crs = crs;
    for (const assess::Feature& f : d.features) {
        Shape shape = shape_of(d, f);
        if (!shape.rings.empty()) {
            layer.extent.add(shape.box);
            layer.shapes.push_back(std::move(shape));
        }
    }
    return layer;
}

struct Opened {
    GDALDatasetUniquePtr dataset;
    OGRLayer* layer = nullptr;
};

Opened open_layer(const std::string& path, const std::string& name, const std::optional<Box>& bbox)
{
    Opened opened{open_input(path), nullptr};
    opened.layer = &select_layer(*opened.dataset, path, name);
    if (bbox) {
        opened.layer->SetSpatialFilterRect(bbox->xmin, bbox->ymin, bbox->xmax, bbox->ymax);
    }
    return opened;
}

std::optional<double> resolve_tolerance(const RenderOptions& o, OGRLayer& layer, const std::optional<assess::SnapReport>& report)
{
    std::optional<double> t = tolerance_option(o.tolerance, o.tolerance_m, layer);
    if (!t && report) {
        t = report->tolerance;
    }
    if (o.worst > 0 && !t) {
        throw argument_error("--worst needs --tolerance T or --tolerance-m M (or a --report that records it): sites are ranked in multiples of T");
    }
    return t;
}

assess::LayerPair read_data(const RenderOptions& o, Opened& in, Opened& out)
{
    try {
        if (!out.dataset) {
            return assess::read_single({*in.dataset, *in.layer}, o.key);
        }
        return assess::read_pair({*in.dataset, *in.layer}, {*out.dataset, *out.layer}, o.key);
    } catch (const std::invalid_argument& e) {
        throw argument_error(e.what());
    }
}

/// The files the picture must never replace; refuses -o when it is one of them (as `snap`
/// refuses an OUT or a report that is a file of its input).
ProtectedFiles protect_inputs(const RenderOptions& o, Opened& in, Opened& out)
{
    ProtectedFiles protect;
    protect.add_dataset(*in.dataset, "the input " + o.input);
    if (out.dataset) {
        protect.add_dataset(*out.dataset, "SNAPPED " + o.snapped);
    }
    if (!o.report.empty()) {
        protect.add_file(o.report, "the report " + o.report);
    }
    check_text_file_target(o.output, protect, "-o");
    return protect;
}

} // namespace

Inputs read_inputs(const RenderOptions& o)
{
    Inputs inputs;
    if (!o.report.empty()) {
        inputs.report = assess::read_snap_report(o.report);
    }
    Opened in = open_layer(o.input, o.layer_a, o.bbox);
    Opened out = o.snapped.empty() ? Opened{} : open_layer(o.snapped, o.layer_b, o.bbox);
    inputs.protect = protect_inputs(o, in, out);
    inputs.tolerance = resolve_tolerance(o, *in.layer, inputs.report);
    const CrsInfo crs = crs_info(in.layer->GetSpatialRef());
    inputs.data = read_data(o, in, out);
    inputs.in = layer_of(inputs.data.a, o.input, crs);
    if (!o.snapped.empty()) {
        inputs.out = layer_of(inputs.data.b, o.snapped, crs);
    }
    return inputs;
}

} // namespace trisnap::render
