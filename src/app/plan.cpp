#include "app/plan.hpp"

#include "config/errors.hpp"
#include "io/dataset.hpp"
#include "io/gdal_errors.hpp"
#include "io/layer_info.hpp"
#include "io/tolerance.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <ostream>

namespace trisnap {
namespace {

void apply_filters(const SnapArgs& args, OGRLayer& layer)
{
    if (!args.where.empty()) {
        ScopedErrorCapture capture;
        if (layer.SetAttributeFilter(args.where.c_str()) != OGRERR_NONE)
            throw argument_error("--where '" + args.where + "': " + capture.last_error("invalid filter"));
        // Some drivers (GPKG) only compile the filter when reading: probe one feature.
        OGRFeatureUniquePtr probe(layer.GetNextFeature());
        layer.ResetReading();
        if (!capture.errors().empty())
            throw argument_error("--where '" + args.where + "': " + capture.last_error());
    }
    if (!args.bbox.empty()) {
        const std::vector<double> b = parse_bbox(args.bbox);
        layer.SetSpatialFilterRect(b[0], b[1], b[2], b[3]);
    }
}

double resolve_tolerance(const Config& config, OGRLayer& layer, std::string& note)
{
    if (config.snap.tolerance_m) return tolerance_from_metres(*config.snap.tolerance_m, layer, note);
    if (!config.snap.tolerance)
        throw argument_error("no tolerance: give --tolerance T (layer units) or --tolerance-m M");
    const double t = *config.snap.tolerance;
    const OGRSpatialReference* srs = layer.GetSpatialRef();
    note = "layer units";
    if (srs && srs->IsGeographic()) {
        note = "degrees";
        if (t >= 0.001)
            spdlog::warn("--tolerance {} is in degrees on this geographic CRS (>= {:.0f} m); "
                         "for metres use --tolerance-m", t, t * metres_per_degree(0) * 0.99);
    }
    return t;
}

SnapOptions engine_options(const Config& config, double tolerance)
{
    SnapOptions o;
    o.tolerance = tolerance;
    o.edge_separation = config.snap.edge_separation;
    o.sliver_factor = config.snap.sliver_factor;
    o.grid = config.snap.grid;
    o.max_drift_factor = config.snap.max_drift_factor;
    o.max_operations = static_cast<std::size_t>(config.snap.max_operations);
    if (std::string reason = validate(o); !reason.empty()) throw argument_error(reason);
    return o;
}

WriteOptions write_options(const SnapArgs& args)
{
    WriteOptions w;
    w.path = args.output;
    w.format = args.format;
    w.layer_name = args.new_layer_name;
    w.layer_options = args.layer_options;
    w.overwrite = args.overwrite;
    for (const auto& o : w.layer_options)
        if (o.find('=') == std::string::npos) throw argument_error("--lco '" + o + "': expected KEY=VALUE");
    return w;
}

} // namespace

Plan make_plan(const SnapArgs& args, const Config& config)
{
    if (args.input.empty()) throw argument_error("missing IN: trisnap snap IN OUT --tolerance T");
    if (args.output.empty()) throw argument_error("missing OUT: trisnap snap IN OUT --tolerance T");
    Plan plan;
    plan.config = config;
    plan.write = write_options(args);
    GDALDriver& driver = output_driver(plan.write.path, plan.write.format);
    plan.output_driver = driver.GetDescription();
    plan.keeps_fids = driver_keeps_fids(driver);
    check_output_path(plan.write, args.input);
    plan.input_path = args.input;
    plan.dataset = open_input(args.input);
    plan.input_driver = plan.dataset->GetDriverName();
    plan.layer = &select_layer(*plan.dataset, args.input, args.layer);
    plan.crs = describe_crs(plan.layer->GetSpatialRef());
    apply_filters(args, *plan.layer);
    if (plan.input_driver != "OSM") plan.feature_count = plan.layer->GetFeatureCount(TRUE);
    plan.tolerance = resolve_tolerance(config, *plan.layer, plan.tolerance_note);
    plan.options = engine_options(config, plan.tolerance);
    plan.tiled = !config.tiling.no_tiles;
    plan.tiling.plan.tile_size = config.tiling.size;
    plan.tiling.plan.vertex_budget = static_cast<std::size_t>(config.tiling.vertex_budget);
    plan.tiling.halo_factor = config.tiling.halo;
    plan.tiling.max_growth = config.tiling.max_growth;
    plan.tiling.threads = config.run.threads;
    return plan;
}

void print_plan(const Plan& plan, std::ostream& out)
{
    const std::string count = plan.feature_count < 0 ? "unknown until read" : std::to_string(plan.feature_count);
    out << fmt::format("input:     {} ({}), layer '{}', {} features, CRS {}\n", plan.input_path,
                       plan.input_driver, plan.layer->GetName(), count, plan.crs);
    out << fmt::format("tolerance: {} ({})\n", plan.tolerance, plan.tolerance_note);
    out << fmt::format("engine:    edge_separation {}, sliver_factor {}, grid {}, max_drift_factor {}\n",
                       plan.options.edge_separation, plan.options.sliver_factor, plan.options.grid,
                       plan.options.max_drift_factor);
    const std::string name = plan.write.layer_name.empty() ? plan.layer->GetName() : plan.write.layer_name;
    out << fmt::format("output:    {} ({}), layer '{}', FIDs {}\n", plan.write.path, plan.output_driver,
                       name, plan.keeps_fids ? "kept" : "in field orig_fid");
    if (!plan.tiled)
        out << "tiling:    none (one triangulation)\n";
    else
        out << fmt::format("tiling:    {}, halo {} x tolerance (doubles up to {} times)\n",
                           plan.tiling.plan.tile_size > 0 ? fmt::format("regular tiles of side {}", plan.tiling.plan.tile_size)
                                                          : fmt::format("balanced tiles of <= {} vertices", plan.tiling.plan.vertex_budget),
                           plan.tiling.halo_factor, plan.tiling.max_growth);
    out << fmt::format("threads:   {}\n", plan.config.run.threads == 0 ? std::string("all cores")
                                                                        : std::to_string(plan.config.run.threads));
}

} // namespace trisnap
