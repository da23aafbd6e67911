#include "io/reader.hpp"

#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/ogr_geometry.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace trisnap {
namespace {

constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

/// A place for the problem: the first point of the geometry's envelope, else NaN.
void locate(const OGRGeometry* geometry, Problem& problem)
{
    problem.x = problem.y = k_nan;
    if (!geometry || geometry->IsEmpty()) return;
    OGREnvelope envelope;
    geometry->getEnvelope(&envelope);
    if (std::isfinite(envelope.MinX) && std::isfinite(envelope.MinY)) {
        problem.x = envelope.MinX;
        problem.y = envelope.MinY;
    }
}

Problem make_problem(std::int64_t fid, ProblemCode code, std::string message, const OGRGeometry* g)
{
    Problem problem;
    problem.feature_id = fid;
    problem.code = code;
    problem.message = std::move(message);
    locate(g, problem);
    return problem;
}

std::string type_name(const OGRGeometry* g)
{
    return g ? OGRGeometryTypeToName(g->getGeometryType()) : "null";
}

} // namespace

InputFeature classify_feature(OGRFeatureUniquePtr feature)
{
    InputFeature in;
    in.fid = feature->GetFID();
    const OGRGeometry* g = feature->GetGeometryRef();
    Geometry converted;
    switch (from_ogr(g, converted)) {
    case GeometryVerdict::snap:
        in.input_type = wkbFlatten(converted.is_polygonal()
                                       ? (converted.type == Geometry::Type::Polygon ? wkbPolygon : wkbMultiPolygon)
                                       : (converted.type == Geometry::Type::LineString ? wkbLineString : wkbMultiLineString));
        in.geometry = std::move(converted);
        feature->SetGeometryDirectly(nullptr); // the engine's result replaces it
        break;
    case GeometryVerdict::pass_through:
        break;
    case GeometryVerdict::unsupported:
        in.problem = make_problem(in.fid, ProblemCode::unsupported_geometry,
                                  "geometry type " + type_name(g) + " is not snapped; written unchanged", g);
        break;
    case GeometryVerdict::empty:
        in.problem = make_problem(in.fid, ProblemCode::empty_geometry,
                                  std::string(g ? "empty" : "null") + " geometry; written without snapping", g);
        break;
    case GeometryVerdict::non_finite:
        in.problem = make_problem(in.fid, ProblemCode::non_finite_coordinate,
                                  "NaN or infinite coordinate; feature not written", nullptr);
        in.rejected = true;
        break;
    }
    in.feature = std::move(feature);
    return in;
}

LayerReader::LayerReader(GDALDataset& dataset, OGRLayer& layer)
    : m_dataset(dataset), m_layer(layer)
{
    m_interleaved = std::string(dataset.GetDriverName()) == "OSM";
    if (m_interleaved) {
        const std::string sql = std::string("SET interest_layers = ") + layer.GetName();
        dataset.ExecuteSQL(sql.c_str(), nullptr, nullptr);
        dataset.ResetReading();
    } else {
        m_count_hint = layer.GetFeatureCount(FALSE);
        layer.ResetReading();
    }
}

OGRFeatureUniquePtr LayerReader::next_ogr_feature()
{
    if (!m_interleaved) return OGRFeatureUniquePtr(m_layer.GetNextFeature());
    for (;;) {
        OGRLayer* from = nullptr;
        OGRFeatureUniquePtr f(m_dataset.GetNextFeature(&from, nullptr, nullptr, nullptr));
        if (!f || from == &m_layer) return f;
    }
}

std::optional<InputFeature> LayerReader::next()
{
    ScopedErrorCapture capture;
    OGRFeatureUniquePtr f = next_ogr_feature();
    // A null feature after an error is a broken file, not the end of the layer.
    if (!f && !capture.errors().empty()) throw io_error(m_dataset.GetDescription(), m_layer.GetName(), capture.last_error());
    if (!f) return std::nullopt;
    return classify_feature(std::move(f));
}

OGRFeatureUniquePtr LayerReader::next_raw()
{
    ScopedErrorCapture capture;
    OGRFeatureUniquePtr f = next_ogr_feature();
    if (capture.errors().empty()) {
        return f;
    }
    const std::string where = f ? "feature FID " + std::to_string(f->GetFID()) + ": " : "";
    throw io_error(m_dataset.GetDescription(), m_layer.GetName(), where + capture.last_error());
}

} // namespace trisnap
