// bench_compare_tools: runs ONE comparison tool on one OGR layer and writes its output, for
// bench/compare (issue 4, part 2). One tool per process, so the caller's wait4() gives wall time and
// peak RSS per tool; this program also prints its own phases and peak RSS as one JSON object.
//
//   bench_compare_tools isr|sr|geos|floor IN OUT.gpkg --tolerance T [--layer L] [--pixel-factor F] [--json FILE]
//                       [--no-index]
//
// isr / sr: CGAL Snap_rounding_2 (iterated / plain snap rounding, Halperin & Packer 2002) over the
//   layer's ring and line segments, deduplicated as undirected segments (shared boundaries once),
//   zero-length ones dropped, at pixel size F*T. CGAL returns one polyline per input segment: OUT gets
//   a line layer `segments` (the deduplicated input, FID i+1) and a line layer `isr`/`sr` (segment
//   i's polyline, FID i+1; a segment that collapsed to a point is not written), so `trisnap assess`
//   can match them by FID. Pixel centres are exact rationals, written rounded to double.
// geos: GEOSGeom_setPrecision(g, T, 0) per feature (GEOS >= 3.9: OverlayNG, valid output), the
//   input's fields and FIDs kept, polygons as MultiPolygon, lines as MultiLineString; an empty
//   result is written as an empty geometry, a GEOS failure leaves the feature out (both counted).
// floor: what any CDT-based snapper must at least do, for the "within 2x of the floor" target:
//   read the layer (features with their fields, as trisnap and geos do), build CGAL's plain
//   constrained Delaunay triangulation (Epick, exact predicates, crossings constructed in doubles)
//   of its unique ring and line segments in one bulk insertion, and write the features unchanged
//   (same fields, FIDs, geometry) in one transaction. T is ignored.
// OUT's layers get GDAL's spatial index (its default; GDAL 3.6 builds it with one SQLite insertion
// per feature), or none with --no-index: trisnap bulk loads its own (io/gpkg_rtree.hpp), so
// anchors without an index are the strictest comparison for its write.
// Exit codes: 0 ok, 1 I/O or tool error, 2 bad arguments.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Snap_rounding_2.h>
#include <CGAL/Snap_rounding_traits_2.h>

#include <CLI/CLI.hpp>
#include <gdal_priv.h>
#include <geos_c.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <list>
#include <memory>
#include <stdexcept>
#include <string>
#include <sys/resource.h>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;
using Segment = std::array<double, 4>; // x0 y0 x1 y1, (x0,y0) < (x1,y1) lexicographically

struct io_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double seconds_since(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

double peak_rss_mb()
{
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0; // KiB on Linux
}

struct DatasetCloser {
    void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

struct Input {
    DatasetPtr dataset;
    OGRLayer* layer = nullptr;
    std::string name;
};

/// Opens IN and the layer: the named one, or the only one when no name is given.
Input open_input(const std::string& path, const std::string& layer_name)
{
    Input in;
    in.dataset.reset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!in.dataset) throw io_error(path + ": cannot open as a vector dataset: " + CPLGetLastErrorMsg());
    if (!layer_name.empty()) {
        in.layer = in.dataset->GetLayerByName(layer_name.c_str());
        if (!in.layer) throw io_error(path + ": no layer '" + layer_name + "'");
    } else {
        if (in.dataset->GetLayerCount() != 1) throw io_error(path + ": several layers, choose one with --layer");
        in.layer = in.dataset->GetLayer(0);
    }
    in.name = in.layer->GetName();
    return in;
}

DatasetPtr create_output(const std::string& path)
{
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
    if (!driver) throw io_error("GDAL has no GPKG driver");
    VSIUnlink(path.c_str());
    DatasetPtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) throw io_error(path + ": cannot create: " + CPLGetLastErrorMsg());
    return ds;
}

bool g_no_index = false; ///< --no-index

OGRLayer* create_layer(GDALDataset& ds, const std::string& name, const OGRSpatialReference* srs,
                       OGRwkbGeometryType type)
{
    char* no_index[] = {const_cast<char*>("SPATIAL_INDEX=NO"), nullptr};
    OGRLayer* layer = ds.CreateLayer(name.c_str(), const_cast<OGRSpatialReference*>(srs), type,
                                     g_no_index ? no_index : nullptr); // GDAL 3.6 API takes non-const
    if (!layer) throw io_error(ds.GetDescription() + std::string(": cannot create layer ") + name);
    return layer;
}

void write_feature(OGRLayer& layer, OGRFeature& feature)
{
    if (layer.CreateFeature(&feature) != OGRERR_NONE)
        throw io_error(std::string(layer.GetName()) + ": cannot write feature " +
                       std::to_string(feature.GetFID()) + ": " + CPLGetLastErrorMsg());
}

// ---------------------------------------------------------------- CGAL snap rounding

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Traits = CGAL::Snap_rounding_traits_2<Kernel>;
using Polyline = std::list<Kernel::Point_2>;

void add_curve_segments(const OGRSimpleCurve& curve, std::vector<Segment>& out)
{
    for (int i = 0; i + 1 < curve.getNumPoints(); ++i) {
        std::array<double, 2> a{curve.getX(i), curve.getY(i)}, b{curve.getX(i + 1), curve.getY(i + 1)};
        if (a == b) continue;
        if (b < a) std::swap(a, b);
        out.push_back({a[0], a[1], b[0], b[1]});
    }
}

/// Every ring and line segment of g (curves linearised, points ignored).
void add_segments(const OGRGeometry& g, std::vector<Segment>& out)
{
    switch (wkbFlatten(g.getGeometryType())) {
    case wkbLineString:
    case wkbLinearRing: add_curve_segments(*g.toSimpleCurve(), out); return;
    case wkbPolygon:
        for (const OGRLinearRing* ring : *g.toPolygon()) add_curve_segments(*ring, out);
        return;
    case wkbMultiPolygon:
    case wkbMultiLineString:
    case wkbGeometryCollection:
        for (const OGRGeometry* part : *g.toGeometryCollection()) add_segments(*part, out);
        return;
    default:
        if (g.hasCurveGeometry()) {
            std::unique_ptr<OGRGeometry> linear(g.getLinearGeometry());
            if (linear) add_segments(*linear, out);
        }
    }
}

std::vector<Segment> read_unique_segments(OGRLayer& layer, Json& stats)
{
    std::vector<Segment> segments;
    std::int64_t features = 0;
    layer.ResetReading();
    for (const auto& feature : layer) {
        ++features;
        if (const OGRGeometry* g = feature->GetGeometryRef()) add_segments(*g, segments);
    }
    stats["features_in"] = features;
    stats["segments_in"] = segments.size();
    std::sort(segments.begin(), segments.end());
    segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
    stats["segments_unique"] = segments.size();
    return segments;
}

void write_segments(GDALDataset& out, const OGRSpatialReference* srs, const std::vector<Segment>& segments)
{
    OGRLayer* layer = create_layer(out, "segments", srs, wkbLineString);
    OGRFeature feature(layer->GetLayerDefn());
    for (std::size_t i = 0; i < segments.size(); ++i) {
        OGRLineString line;
        line.addPoint(segments[i][0], segments[i][1]);
        line.addPoint(segments[i][2], segments[i][3]);
        feature.SetFID(static_cast<GIntBig>(i + 1));
        feature.SetGeometry(&line);
        write_feature(*layer, feature);
    }
}

/// Polyline i -> feature i+1; polylines of one point (collapsed segments) are counted, not written.
void write_polylines(GDALDataset& out, const std::string& name, const OGRSpatialReference* srs,
                     const std::list<Polyline>& polylines, Json& stats)
{
    OGRLayer* layer = create_layer(out, name, srs, wkbLineString);
    OGRFeature feature(layer->GetLayerDefn());
    std::int64_t fid = 0, collapsed = 0, vertices = 0;
    for (const Polyline& polyline : polylines) {
        ++fid;
        if (polyline.size() < 2) {
            ++collapsed;
            continue;
        }
        OGRLineString line;
        for (const Kernel::Point_2& p : polyline) line.addPoint(CGAL::to_double(p.x()), CGAL::to_double(p.y()));
        vertices += line.getNumPoints();
        feature.SetFID(fid);
        feature.SetGeometry(&line);
        write_feature(*layer, feature);
    }
    stats["polylines_out"] = fid - collapsed;
    stats["collapsed_segments"] = collapsed;
    stats["output_vertices"] = vertices;
}

void run_snap_rounding(bool iterated, Input& in, const std::string& out_path, double pixel, Json& stats)
{
    auto start = Clock::now();
    const std::vector<Segment> segments = read_unique_segments(*in.layer, stats);
    std::vector<Kernel::Segment_2> cgal_segments;
    cgal_segments.reserve(segments.size());
    for (const Segment& s : segments)
        cgal_segments.emplace_back(Kernel::Point_2(s[0], s[1]), Kernel::Point_2(s[2], s[3]));
    stats["read_s"] = seconds_since(start);

    start = Clock::now();
    std::list<Polyline> polylines;
    // int_output = false: pixel centres in layer units, not integer grid indices.
    CGAL::snap_rounding_2<Traits>(cgal_segments.begin(), cgal_segments.end(), polylines, pixel, iterated, false);
    stats["compute_s"] = seconds_since(start);

    start = Clock::now();
    DatasetPtr out = create_output(out_path);
    const OGRSpatialReference* srs = in.layer->GetSpatialRef();
    out->StartTransaction(TRUE);
    write_segments(*out, srs, segments);
    write_polylines(*out, iterated ? "isr" : "sr", srs, polylines, stats);
    if (out->CommitTransaction() != OGRERR_NONE) throw io_error(out_path + ": cannot commit: " + CPLGetLastErrorMsg());
    out.reset();
    stats["write_s"] = seconds_since(start);
}

// ---------------------------------------------------------------- GEOS precision reducer

struct GeosContext {
    GEOSContextHandle_t handle = GEOS_init_r();
    ~GeosContext() { GEOS_finish_r(handle); }
};

/// g reduced to the grid, as OGR; nullptr when GEOS fails on it.
std::unique_ptr<OGRGeometry> set_precision(GEOSContextHandle_t ctx, const OGRGeometry& g, double grid)
{
    std::vector<unsigned char> wkb(static_cast<std::size_t>(g.WkbSize()));
    g.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
    GEOSGeometry* in = GEOSGeomFromWKB_buf_r(ctx, wkb.data(), wkb.size());
    if (!in) return nullptr;
    GEOSGeometry* reduced = GEOSGeom_setPrecision_r(ctx, in, grid, 0);
    GEOSGeom_destroy_r(ctx, in);
    if (!reduced) return nullptr;
    std::size_t size = 0;
    unsigned char* out = GEOSGeomToWKB_buf_r(ctx, reduced, &size);
    GEOSGeom_destroy_r(ctx, reduced);
    if (!out) return nullptr;
    OGRGeometry* result = nullptr;
    OGRGeometryFactory::createFromWkb(out, nullptr, &result, size);
    GEOSFree_r(ctx, out);
    return std::unique_ptr<OGRGeometry>(result);
}

bool is_polygonal(OGRwkbGeometryType type)
{
    type = wkbFlatten(type);
    return type == wkbPolygon || type == wkbMultiPolygon || type == wkbCurvePolygon || type == wkbMultiSurface;
}

/// The output layer's type: polygons unless the input layer (or its first geometry) is lines.
OGRwkbGeometryType output_type(OGRLayer& layer)
{
    OGRwkbGeometryType type = wkbFlatten(layer.GetGeomType());
    if (type == wkbUnknown) {
        layer.ResetReading();
        for (const auto& feature : layer)
            if (const OGRGeometry* g = feature->GetGeometryRef()) {
                type = wkbFlatten(g->getGeometryType());
                break;
            }
    }
    return is_polygonal(type) || type == wkbUnknown ? wkbMultiPolygon : wkbMultiLineString;
}

void run_geos(Input& in, const std::string& out_path, double grid, Json& stats)
{
    const OGRwkbGeometryType type = output_type(*in.layer);
    DatasetPtr out = create_output(out_path);
    OGRLayer* layer = create_layer(*out, in.name, in.layer->GetSpatialRef(), type);
    OGRFeatureDefn* in_defn = in.layer->GetLayerDefn();
    for (int i = 0; i < in_defn->GetFieldCount(); ++i)
        if (layer->CreateField(in_defn->GetFieldDefn(i)) != OGRERR_NONE)
            throw io_error(out_path + ": cannot create field " + in_defn->GetFieldDefn(i)->GetNameRef());
    out->StartTransaction(TRUE);
    GeosContext geos;
    double reduce_s = 0;
    std::int64_t features = 0, empty = 0, failed = 0, vertices = 0;
    const auto start = Clock::now();
    in.layer->ResetReading();
    for (const auto& feature : *in.layer) {
        ++features;
        OGRFeature copy(layer->GetLayerDefn());
        copy.SetFrom(feature.get(), TRUE);
        copy.SetFID(feature->GetFID());
        if (const OGRGeometry* g = feature->GetGeometryRef()) {
            const auto reduce_start = Clock::now();
            std::unique_ptr<OGRGeometry> reduced = set_precision(geos.handle, *g, grid);
            reduce_s += seconds_since(reduce_start);
            if (!reduced) {
                ++failed;
                continue;
            }
            if (reduced->IsEmpty()) ++empty;
            OGRGeometry* forced = type == wkbMultiPolygon ? OGRGeometryFactory::forceToMultiPolygon(reduced.release())
                                                          : OGRGeometryFactory::forceToMultiLineString(reduced.release());
            if (!forced->IsEmpty()) vertices += OGR_G_GetPointCount(OGRGeometry::ToHandle(forced));
            copy.SetGeometryDirectly(forced);
        }
        write_feature(*layer, copy);
    }
    if (out->CommitTransaction() != OGRERR_NONE) throw io_error(out_path + ": cannot commit: " + CPLGetLastErrorMsg());
    out.reset();
    stats["features_in"] = features;
    stats["features_out"] = features - failed;
    stats["empty_out"] = empty;
    stats["geos_failures"] = failed;
    stats["compute_s"] = reduce_s;
    stats["read_write_s"] = seconds_since(start) - reduce_s;
    stats["geos_version"] = GEOSversion();
}

} // namespace

// ---------------------------------------------------------------- the read + CDT + write floor

using FloorKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using FloorCdt = CGAL::Constrained_Delaunay_triangulation_2<FloorKernel, CGAL::Default, CGAL::Exact_predicates_tag>;

/// Copies every feature (fields, FID, geometry) to OUT while collecting its segments.
void copy_layer(Input& in, GDALDataset& out, std::vector<Segment>& segments, Json& stats)
{
    OGRLayer* layer = create_layer(out, in.name, in.layer->GetSpatialRef(), in.layer->GetGeomType());
    OGRFeatureDefn* in_defn = in.layer->GetLayerDefn();
    for (int i = 0; i < in_defn->GetFieldCount(); ++i) {
        if (layer->CreateField(in_defn->GetFieldDefn(i)) != OGRERR_NONE) {
            throw io_error(std::string("cannot create field ") + in_defn->GetFieldDefn(i)->GetNameRef());
        }
    }
    std::int64_t features = 0;
    in.layer->ResetReading();
    for (const auto& feature : *in.layer) {
        ++features;
        if (const OGRGeometry* g = feature->GetGeometryRef()) {
            add_segments(*g, segments);
        }
        OGRFeature copy(layer->GetLayerDefn());
        copy.SetFrom(feature.get(), TRUE);
        copy.SetFID(feature->GetFID());
        write_feature(*layer, copy);
    }
    stats["features_in"] = features;
    stats["features_out"] = features;
}

void run_floor(Input& in, const std::string& out_path, Json& stats)
{
    auto start = Clock::now();
    DatasetPtr out = create_output(out_path);
    out->StartTransaction(TRUE);
    std::vector<Segment> segments;
    copy_layer(in, *out, segments, stats);
    std::sort(segments.begin(), segments.end());
    segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
    stats["segments_unique"] = segments.size();
    const double read_write_s = seconds_since(start);
    start = Clock::now();
    std::vector<FloorKernel::Point_2> points;
    std::vector<std::pair<std::size_t, std::size_t>> indices;
    points.reserve(2 * segments.size());
    indices.reserve(segments.size());
    for (const Segment& s : segments) {
        points.emplace_back(s[0], s[1]);
        points.emplace_back(s[2], s[3]);
        indices.emplace_back(points.size() - 2, points.size() - 1);
    }
    FloorCdt cdt;
    cdt.insert_constraints(points.begin(), points.end(), indices.begin(), indices.end());
    stats["cdt_vertices"] = cdt.number_of_vertices();
    stats["compute_s"] = seconds_since(start);
    start = Clock::now();
    if (out->CommitTransaction() != OGRERR_NONE) {
        throw io_error(out_path + ": cannot commit: " + CPLGetLastErrorMsg());
    }
    out.reset();
    stats["read_write_s"] = read_write_s + seconds_since(start);
}

int main(int argc, char** argv)
{
    CLI::App app{"run one comparison tool (CGAL ISR/SR or GEOS setPrecision) on one layer; see bench/README.md"};
    std::string tool, in_path, out_path, layer_name, json_path;
    double tolerance = 0, pixel_factor = 1;
    app.add_option("tool", tool, "isr | sr | geos | floor")->required()->check(CLI::IsMember({"isr", "sr", "geos", "floor"}));
    app.add_option("IN", in_path, "input vector dataset")->required();
    app.add_option("OUT", out_path, "output GeoPackage (replaced)")->required();
    app.add_option("--layer", layer_name, "input layer (default: the only one)");
    app.add_option("--tolerance", tolerance, "tolerance T in layer units")->required();
    app.add_option("--pixel-factor", pixel_factor, "ISR/SR pixel size as a factor of T (default 1)");
    app.add_option("--json", json_path, "also write the JSON here");
    app.add_flag("--no-index", g_no_index, "write OUT's layers without a spatial index (SPATIAL_INDEX=NO)");
    try {
        app.parse(argc, argv);
        if (!(tolerance > 0) || !std::isfinite(tolerance)) throw CLI::ValidationError("--tolerance", "must be finite and > 0");
        if (!(pixel_factor > 0) || !std::isfinite(pixel_factor)) throw CLI::ValidationError("--pixel-factor", "must be > 0");
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    GDALAllRegister();
    CPLSetErrorHandler(CPLQuietErrorHandler);
    Json stats;
    stats["tool"] = tool;
    stats["input"] = in_path;
    stats["output"] = out_path;
    stats["tolerance"] = tolerance;
    const auto start = Clock::now();
    try {
        Input in = open_input(in_path, layer_name);
        stats["layer"] = in.name;
        if (tool == "geos") {
            stats["grid"] = tolerance;
            run_geos(in, out_path, tolerance, stats);
        } else if (tool == "floor") {
            run_floor(in, out_path, stats);
        } else {
            stats["pixel"] = pixel_factor * tolerance;
            run_snap_rounding(tool == "isr", in, out_path, pixel_factor * tolerance, stats);
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_compare_tools: error: " << tool << ": " << e.what() << "\n";
        return 1;
    }
    stats["total_s"] = seconds_since(start);
    stats["peak_rss_mb"] = peak_rss_mb();
    std::cout << stats.dump() << "\n";
    if (!json_path.empty()) {
        std::ofstream(json_path) << stats.dump(2) << "\n";
    }
    return 0;
}
