// Reading an OGR layer into flat arrays, sequentially (OGR layers are not thread-safe), and the
// per-feature helpers the measures share.
#include "assess/layer_data.hpp"

#include "io/reader.hpp"

#include <ogrsf_frmts.h>

#include <fmt/format.h>

#include <memory>
#include <stdexcept>

namespace trisnap::assess {
namespace {

bool measurable(double v) { return std::fabs(v) <= k_max_coordinate; } // false for NaN too

void add_curve(LayerData& data, Feature& f, const OGRSimpleCurve& curve, PartType type)
{
    const int n = curve.getNumPoints();
    if (n == 0) {
        return;
    }
    Part part{static_cast<std::uint32_t>(data.pts.size()), 0, type};
    for (int i = 0; i < n; ++i) {
        const Pt p{curve.getX(i), curve.getY(i)};
        if (!measurable(p.x) || !measurable(p.y)) {
            f.kind = FeatureKind::unmeasurable;
        }
        data.pts.push_back(p);
        f.box.add(p);
    }
    if (type != PartType::line && data.pts.back() != data.pts[part.begin]) {
        data.pts.push_back(data.pts[part.begin]);
    }
    part.end = static_cast<std::uint32_t>(data.pts.size());
    data.parts.push_back(part);
}

void add_geometry(LayerData& data, Feature& f, const OGRGeometry& g)
{
    const OGRwkbGeometryType type = wkbFlatten(g.getGeometryType());
    if (g.hasCurveGeometry()) {
        std::unique_ptr<OGRGeometry> linear(g.getLinearGeometry());
        if (linear) {
            add_geometry(data, f, *linear);
        }
    } else if (type == wkbPolygon || type == wkbTriangle) {
        const auto& polygon = *g.toPolygon();
        if (polygon.IsEmpty()) {
            return;
        }
        if (f.kind != FeatureKind::unmeasurable) {
            f.kind = FeatureKind::polygon;
        }
        add_curve(data, f, *polygon.getExteriorRing(), PartType::shell);
        for (int i = 0; i < polygon.getNumInteriorRings(); ++i) {
            add_curve(data, f, *polygon.getInteriorRing(i), PartType::hole);
        }
    } else if (type == wkbLineString || type == wkbLinearRing) {
        if (g.IsEmpty()) {
            return;
        }
        if (f.kind == FeatureKind::empty) {
            f.kind = FeatureKind::line;
        }
        add_curve(data, f, *g.toSimpleCurve(), PartType::line);
    } else if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
        for (const OGRGeometry* member : *g.toGeometryCollection()) {
            add_geometry(data, f, *member);
        }
    } // points and other types carry no segments
}

std::string field_text(const OGRFeature& feature, int index)
{
    if (index < 0 || !feature.IsFieldSetAndNotNull(index)) {
        return "\x01null";
    }
    switch (feature.GetFieldDefnRef(index)->GetType()) {
    case OFTInteger:
    case OFTInteger64: return std::to_string(feature.GetFieldAsInteger64(index));
    case OFTReal: {
        // Numbers compare by value, so 3 (Integer in one format) equals 3.0 (Real in another).
        const double v = feature.GetFieldAsDouble(index);
        if (v == std::floor(v) && std::fabs(v) < 9e15) {
            return std::to_string(static_cast<long long>(v));
        }
        return fmt::format("{:.17g}", v);
    }
    default: return feature.GetFieldAsString(index);
    }
}

/// One feature's geometry into `data`; an unmeasurable feature keeps no points or parts.
void add_feature_geometry(LayerData& data, Feature& f, const OGRGeometry* g)
{
    const std::size_t first_point = data.pts.size();
    f.part_begin = static_cast<std::uint32_t>(data.parts.size());
    if (g) {
        add_geometry(data, f, *g);
    }
    if (f.kind == FeatureKind::unmeasurable) {
        data.pts.resize(first_point);
        data.parts.resize(f.part_begin);
        f.box = Box{};
    } else if (data.parts.size() == f.part_begin) {
        f.kind = FeatureKind::empty;
    }
    f.part_end = static_cast<std::uint32_t>(data.parts.size());
}

} // namespace

LayerData read_layer(GDALDataset& dataset, OGRLayer& layer, const std::string& key_field,
                     const std::vector<std::string>& fields)
{
    LayerData data;
    data.name = layer.GetName();
    data.compared_fields = fields;
    OGRFeatureDefn* defn = layer.GetLayerDefn();
    const int key_index = key_field.empty() ? -1 : defn->GetFieldIndex(key_field.c_str());
    std::vector<int> indexes;
    for (const std::string& name : fields) {
        indexes.push_back(defn->GetFieldIndex(name.c_str()));
    }
    LayerReader reader(dataset, layer);
    for (OGRFeatureUniquePtr in = reader.next_strict(); in; in = reader.next_strict()) {
        Feature f;
        f.fid = in->GetFID();
        f.key = key_index >= 0 ? field_text(*in, key_index) : std::to_string(f.fid);
        add_feature_geometry(data, f, in->GetGeometryRef());
        for (int index : indexes) {
            f.values.push_back(field_text(*in, index));
        }
        data.features.push_back(std::move(f));
    }
    return data;
}

std::size_t LayerData::segment_count(const Feature& f) const
{
    std::size_t n = 0;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        n += parts[i].end - parts[i].begin - 1;
    }
    return n;
}

Pt LayerData::anchor(const Feature& f) const
{
    return f.part_begin < f.part_end ? pts[parts[f.part_begin].begin] : Pt{};
}

double LayerData::length(const Feature& f) const
{
    double total = 0;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        for (std::uint32_t k = parts[i].begin; k + 1 < parts[i].end; ++k) {
            total += distance(pts[k], pts[k + 1]);
        }
    }
    return total;
}

double LayerData::area(const Feature& f) const
{
    double total = 0;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        const Part& part = parts[i];
        if (part.type == PartType::line) {
            continue;
        }
        double twice = 0;
        const Pt o = pts[part.begin]; // relative coordinates keep precision far from the origin
        for (std::uint32_t k = part.begin; k + 1 < part.end; ++k) {
            twice += (pts[k].x - o.x) * (pts[k + 1].y - o.y) - (pts[k + 1].x - o.x) * (pts[k].y - o.y);
        }
        total += (part.type == PartType::shell ? 0.5 : -0.5) * std::fabs(twice);
    }
    return total;
}

OGRGeometry* LayerData::make_ogr_polygon(const Feature& f) const
{
    if (f.kind != FeatureKind::polygon) {
        return nullptr;
    }
    auto multi = std::make_unique<OGRMultiPolygon>();
    std::unique_ptr<OGRPolygon> polygon;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        const Part& part = parts[i];
        if (part.type == PartType::line) {
            continue;
        }
        if (part.type == PartType::shell) {
            if (polygon) {
                multi->addGeometryDirectly(polygon.release());
            }
            polygon = std::make_unique<OGRPolygon>();
        }
        auto ring = std::make_unique<OGRLinearRing>();
        ring->setNumPoints(static_cast<int>(part.end - part.begin), FALSE);
        for (std::uint32_t k = part.begin; k < part.end; ++k) {
            ring->setPoint(static_cast<int>(k - part.begin), pts[k].x, pts[k].y);
        }
        if (polygon) {
            polygon->addRingDirectly(ring.release());
        }
    }
    if (polygon) {
        multi->addGeometryDirectly(polygon.release());
    }
    if (multi->getNumGeometries() == 1) {
        OGRGeometry* single = multi->getGeometryRef(0)->clone();
        return single;
    }
    return multi.release();
}

bool LayerData::strictly_inside(const Feature& f, Pt p) const
{
    bool inside = false;
    for (std::uint32_t i = f.part_begin; i < f.part_end; ++i) {
        const Part& part = parts[i];
        if (part.type == PartType::line) {
            continue;
        }
        for (std::uint32_t k = part.begin; k + 1 < part.end; ++k) {
            const Pt a = pts[k], b = pts[k + 1];
            if ((a.y > p.y) == (b.y > p.y)) {
                if (a.y == p.y && b.y == p.y && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x)) {
                    return false;
                }
                continue;
            }
            const int o = orient(a, b, p);
            if (o == 0) return false; // on the boundary
            if ((o > 0) == (b.y > a.y)) inside = !inside; // p is left of an upward edge: ray crosses it
        }
    }
    return inside;
}

} // namespace trisnap::assess
