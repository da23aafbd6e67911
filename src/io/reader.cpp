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

bool is_null_or_empty(const OGRGeometry* g)
{
    return g == nullptr || g->IsEmpty();
}

/// A feature whose geometry the driver failed to read (a garbage blob, a .shp cut short): GDAL
/// hands back a null geometry and an error. Writing it as a null geometry would pass off lost
/// data as a feature without geometry, so it is rejected with GDAL's message.
InputFeature unreadable(OGRFeatureUniquePtr feature, const std::string& gdal_message)
{
    InputFeature in;
    in.fid = feature->GetFID();
    in.problem = make_problem(in.fid, ProblemCode::unreadable_geometry,
                              "the geometry cannot be read (GDAL: " + gdal_message + "); feature not written", nullptr);
    in.rejected = true;
    in.feature = std::move(feature);
    return in;
}

OGRwkbGeometryType ogr_type(const Geometry& g)
{
    switch (g.type) {
    case Geometry::Type::Polygon:
        return wkbPolygon;
    case Geometry::Type::MultiPolygon:
        return wkbMultiPolygon;
    case Geometry::Type::LineString:
        return wkbLineString;
    default:
        return wkbMultiLineString;
    }
}

void note_non_finite_z(InputFeature& in, const ReadNotes& notes, const OGRGeometry* g)
{
    if (notes.non_finite_z == 0) {
        return;
    }
    const std::string message = std::to_string(notes.non_finite_z) +
                                " vertices with NaN or infinite Z; they lose their Z (0 unless merged with a vertex that has one)";
    in.problem = make_problem(in.fid, ProblemCode::non_finite_z, message, g);
}

} // namespace

InputFeature classify_feature(OGRFeatureUniquePtr feature)
{
    InputFeature in;
    in.fid = feature->GetFID();
    const OGRGeometry* g = feature->GetGeometryRef();
    Geometry converted;
    ReadNotes notes;
    switch (from_ogr(g, converted, notes)) {
    case GeometryVerdict::snap:
        in.input_type = ogr_type(converted);
        in.geometry = std::move(converted);
        note_non_finite_z(in, notes, g);
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

LayerReader::LayerReader(GDALDataset& dataset, OGRLayer& layer, const std::vector<OGRLayer*>& interest)
    : m_dataset(dataset), m_layer(layer)
{
    m_interleaved = std::string(dataset.GetDriverName()) == "OSM";
    if (m_interleaved) {
        std::string names = layer.GetName();
        for (OGRLayer* other : interest) {
            if (other != &layer) {
                names += std::string(",") + other->GetName();
            }
        }
        const std::string sql = "SET interest_layers = " + names;
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

OGRFeatureUniquePtr LayerReader::next_raw()
{
    ScopedErrorCapture capture;
    OGRFeatureUniquePtr f = next_ogr_feature();
    // A null feature after an error is a broken file, not the end of the layer.
    if (!f && !capture.errors().empty()) {
        throw io_error(m_dataset.GetDescription(), m_layer.GetName(), capture.last_error());
    }
    m_feature_error = capture.errors().empty() ? "" : capture.last_error();
    return f;
}

std::optional<InputFeature> LayerReader::next()
{
    OGRFeatureUniquePtr f = next_raw();
    if (!f) {
        return std::nullopt;
    }
    if (!m_feature_error.empty() && is_null_or_empty(f->GetGeometryRef())) {
        return unreadable(std::move(f), m_feature_error);
    }
    return classify_feature(std::move(f));
}

OGRFeatureUniquePtr LayerReader::next_strict()
{
    OGRFeatureUniquePtr f = next_raw();
    if (f && !m_feature_error.empty()) {
        throw io_error(m_dataset.GetDescription(), m_layer.GetName(),
                       "feature FID " + std::to_string(f->GetFID()) + ": " + m_feature_error);
    }
    return f;
}

} // namespace trisnap
