#include "app/plan.hpp"

#include "app/allocator.hpp"

#include "app/text.hpp"
#include "config/errors.hpp"
#include "io/commit_group.hpp"
#include "io/dataset.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"
#include "io/layer_info.hpp"
#include "io/output_driver.hpp"
#include "io/problems_layer.hpp"
#include "io/tolerance.hpp"
#include "io/update_target.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <ostream>
#include <sstream>

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
    if (args.bbox) {
        const std::vector<double> b = parse_bbox(*args.bbox);
        layer.SetSpatialFilterRect(b[0], b[1], b[2], b[3]);
    }
}

double resolve_tolerance(const Config& config, OGRLayer& layer, std::string& note)
{
    if (config.snap.tolerance_m) {
        std::string warning;
        const double t = tolerance_from_metres(*config.snap.tolerance_m, layer, note, &warning);
        if (!warning.empty()) {
            spdlog::warn("{}", warning);
        }
        return t;
    }
    if (!config.snap.tolerance)
        throw argument_error("no tolerance: give --tolerance T (layer units) or --tolerance-m M");
    const double t = *config.snap.tolerance;
    const OGRSpatialReference* srs = layer.GetSpatialRef();
    note = "layer units";
    if (srs && srs->IsGeographic()) {
        note = "degrees";
    }
    if (degrees_above_warning(t, false, srs)) {
        spdlog::warn("{}", degree_warning(t, layer));
    }
    return t;
}

WriteOptions write_options(const SnapArgs& args)
{
    check_key_values(args.layer_options, "--lco");
    check_key_values(args.dataset_options, "--dsco");
    WriteOptions w;
    w.path = args.output == "-" ? "/vsistdout/" : args.output;
    w.format = args.format;
    w.layer_name = args.new_layer_name;
    w.layer_options = args.layer_options;
    w.dataset_options = args.dataset_options;
    w.fields = split_list(args.select);
    w.overwrite = args.overwrite;
    w.update = args.update;
    w.append = args.append;
    return w;
}

/// What the pipeline would refuse after reading everything: refuse it before reading. With
/// several layers, only when none has a feature (an empty one is written empty).
void check_not_empty(const Plan& plan)
{
    if (plan.feature_count != 0) {
        return;
    }
    const bool filtered = plan.layer->GetAttrQueryString() || plan.layer->GetSpatialFilter();
    throw io_error(input_label(plan), "",
                   filtered ? "no feature matches --where/--bbox: nothing to snap" : "the layer is empty: nothing to snap");
}

/// OUT, --report and --problems-layer are three files: one written over another loses data.
void check_distinct(const std::vector<std::pair<std::string, std::string>>& files)
{
    for (std::size_t i = 0; i < files.size(); ++i) {
        for (std::size_t j = i + 1; j < files.size(); ++j) {
            const auto a = std::filesystem::weakly_canonical(files[i].second);
            if (!files[i].second.empty() && a == std::filesystem::weakly_canonical(files[j].second)) {
                throw argument_error(files[i].first + " and " + files[j].first + " are the same file (" +
                                     files[i].second + "); give each its own");
            }
        }
    }
}

/// --problems-layer naming OUT itself: a layer "problems" written into it after the output
/// layer, when OUT is a GeoPackage written with --overwrite, --update or --append.
bool problems_beside_output(const SnapArgs& args, const Plan& plan)
{
    namespace fs = std::filesystem;
    const bool updates = args.overwrite || args.update || args.append;
    bool named_problems = false;
    for (std::size_t k = 0; k < plan.layers.size(); ++k) {
        named_problems = named_problems || output_layer_name(plan, k) == "problems";
    }
    return updates && plan.output_driver == "GPKG" && !named_problems && !args.problems_layer.empty() &&
           fs::weakly_canonical(args.problems_layer) == fs::weakly_canonical(plan.write.path);
}

/// Several layers go to one OUT, a layer each under its own name.
void check_several_outputs(const SnapArgs& args, const Plan& plan, GDALDriver& driver)
{
    if (plan.layers.size() < 2) {
        return;
    }
    if (!args.new_layer_name.empty()) {
        throw argument_error("-nln " + args.new_layer_name + ": it names one output layer, and " +
                             std::to_string(plan.layers.size()) + " layers were given (" + layers_label(plan) +
                             "); each is written to a layer of its own name in OUT");
    }
    if (!holds_layers(driver)) {
        throw argument_error(args.output + ": the " + std::string(driver.GetDescription()) + " format holds one layer per " +
                             "file, and " + layers_label(plan) + " go to one OUT; write them to a format that holds " +
                             "several, e.g. " + std::filesystem::path(args.output).stem().string() + ".gpkg");
    }
}

void check_outputs(const SnapArgs& args, Plan& plan, GDALDriver& driver)
{
    check_several_outputs(args, plan, driver);
    plan.write.renamable = plan.layers.size() == 1;
    for (OGRLayer* layer : plan.layers) {
        probe_output(driver, plan.write, *layer);
        check_update_target(plan.write, driver, *layer);
    }
    check_report_path(args.report);
    if (!args.problems_layer.empty()) {
        check_problems_layer_path(args.problems_layer, args.overwrite, args.update || args.append);
    }
    const std::string problems = problems_beside_output(args, plan) ? "" : args.problems_layer;
    check_distinct({{"OUT", plan.write.path}, {"--report", args.report}, {"--problems-layer", problems}});
}

/// --layer given more than once: distinct layers of one CRS. From an OSM file too: its driver
/// reads interleaved, and the reader (io/reader.hpp) reads the file once per layer, that layer
/// alone of interest.
std::vector<OGRLayer*> several_layers(const SnapArgs& args, GDALDataset& dataset)
{
    std::vector<OGRLayer*> layers;
    for (std::size_t k = 0; k < args.layers.size(); ++k) {
        for (std::size_t j = 0; j < k; ++j) {
            if (args.layers[j] == args.layers[k]) {
                throw argument_error("--layer " + args.layers[k] + " is given twice; name each layer once");
            }
        }
        layers.push_back(&select_layer(dataset, args.input, args.layers[k]));
    }
    const OGRSpatialReference* first = layers[0]->GetSpatialRef();
    for (std::size_t k = 1; k < layers.size(); ++k) {
        const OGRSpatialReference* crs = layers[k]->GetSpatialRef();
        const bool same = (first == nullptr && crs == nullptr) || (first && crs && first->IsSame(crs));
        if (!same) {
            throw argument_error(fmt::format("--layer {} and --layer {} have different CRSs ({}: {}; {}: {}): layers "
                                             "snapped together need one; reproject one first (ogr2ogr -t_srs)",
                                             args.layers[0], args.layers[k], args.layers[0], describe_crs(first),
                                             args.layers[k], describe_crs(crs)));
        }
    }
    return layers;
}

/// The input half of a plan: the dataset, the layers, their filters and feature counts.
void open_layer(const SnapArgs& args, Plan& plan)
{
    plan.input_path = args.input;
    check_key_values(args.open_options, "--oo");
    plan.dataset = open_input(args.input, args.open_options);
    plan.open_options = args.open_options;
    plan.input_driver = plan.dataset->GetDriverName();
    if (args.layers.size() > 1) {
        plan.layers = several_layers(args, *plan.dataset);
    } else {
        plan.layers = {&select_layer(*plan.dataset, args.input, args.layers.empty() ? "" : args.layers[0])};
    }
    plan.layer = plan.layers.front();
    plan.crs = describe_crs(plan.layer->GetSpatialRef());
    plan.feature_count = plan.input_driver == "OSM" ? -1 : 0;
    for (OGRLayer* layer : plan.layers) {
        apply_filters(args, *layer);
        plan.feature_counts.push_back(plan.input_driver == "OSM" ? -1 : layer->GetFeatureCount(TRUE));
        if (plan.feature_count >= 0) {
            plan.feature_count += plan.feature_counts.back();
        }
    }
    check_not_empty(plan);
}

/// What the engine and the tiles get: the tolerance in layer units, engine and tiling options.
void resolve_engine(const SnapArgs& args, const Config& config, Plan& plan)
{
    plan.tolerance = resolve_tolerance(config, *plan.layer, plan.tolerance_note);
    plan.options = engine_options(config, plan.tolerance);
    plan.bbox = args.bbox.value_or("");
    plan.tiling = tiling_options(config);
}

/// The plan as info lines (-v), the same text `validate` prints.
void log_plan(const Plan& plan)
{
    std::ostringstream text;
    print_plan(plan, text);
    std::istringstream lines(text.str());
    for (std::string line; std::getline(lines, line);) {
        spdlog::info("{}", line);
    }
    spdlog::info("memory:    heap in {}", describe(huge_page_choice()));
}

/// No output may be, or replace, a file of the input dataset (compared by real path and
/// inode, every file GDAL lists): not OUT or any file its driver writes, not the report or the
/// problems layer.
void protect_input(Plan& plan, const SnapArgs& args, GDALDriver& driver)
{
    plan.write.protected_files.add_dataset(*plan.dataset, "the input " + args.input);
    check_output_files(plan.write, driver);
    ProtectedFiles taken = plan.write.protected_files;
    for (const std::string& file : dataset_files_for(plan.write.path, driver)) {
        taken.add_file(file, "OUT " + plan.write.path);
    }
    if (!args.report.empty()) {
        check_text_file_target(args.report, taken, "--report");
    }
    if (!args.problems_layer.empty()) {
        const bool beside = problems_beside_output(args, plan); // OUT's file, but never the input's
        check_text_file_target(args.problems_layer, beside ? plan.write.protected_files : taken, "--problems-layer");
    }
}

} // namespace

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

stitch::TilingOptions tiling_options(const Config& config)
{
    stitch::TilingOptions t;
    t.plan.single = config.tiling.no_tiles;
    t.plan.tile_size = config.tiling.size;
    t.plan.vertex_budget = static_cast<std::size_t>(config.tiling.vertex_budget);
    t.halo_factor = config.tiling.halo;
    t.max_growth = config.tiling.max_growth;
    t.threads = config.run.threads;
    t.on_error = config.run.on_error == "skip" ? stitch::OnError::skip : stitch::OnError::stop;
    return t;
}

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
    open_layer(args, plan);
    protect_input(plan, args, driver);
    check_outputs(args, plan, driver);
    resolve_engine(args, config, plan);
    log_plan(plan);
    return plan;
}

Plan make_input_plan(const SnapArgs& args, const Config& config)
{
    if (args.input.empty()) {
        throw argument_error("missing IN: trisnap plan IN RUN_DIR --tolerance T");
    }
    Plan plan;
    plan.config = config;
    open_layer(args, plan);
    resolve_engine(args, config, plan);
    return plan;
}

std::string output_layer_name(const Plan& plan, std::size_t k)
{
    return plan.write.layer_name.empty() ? plan.layers[k]->GetName() : plan.write.layer_name;
}

std::string layers_label(const Plan& plan)
{
    std::string names;
    for (OGRLayer* layer : plan.layers) {
        names += fmt::format("{}'{}'", names.empty() ? "" : ", ", layer->GetName());
    }
    return (plan.layers.size() > 1 ? "layers " : "layer ") + names;
}

std::string input_label(const Plan& plan)
{
    return plan.input_path + " (" + layers_label(plan) + ")";
}

void print_plan(const Plan& plan, std::ostream& out)
{
    const std::string count = plan.feature_count < 0 ? "features unknown until read" : count_of(plan.feature_count, "feature");
    if (plan.layers.size() > 1) {
        std::string each;
        for (std::size_t k = 0; k < plan.layers.size(); ++k) {
            each += fmt::format("{}'{}' ({})", k ? ", " : "", plan.layers[k]->GetName(), count_of(plan.feature_counts[k], "feature"));
        }
        out << fmt::format("input:     {} ({}), layers {}, {} in all, snapped together, CRS {}\n", plan.input_path,
                           plan.input_driver, each, count, plan.crs);
    } else {
        out << fmt::format("input:     {} ({}), layer '{}', {}, CRS {}\n", plan.input_path,
                           plan.input_driver, plan.layer->GetName(), count, plan.crs);
    }
    out << fmt::format("tolerance: {} ({})\n", plan.tolerance, plan.tolerance_note);
    out << fmt::format("engine:    edge_separation {}, sliver_factor {}, grid {}, max_drift_factor {}\n",
                       plan.options.edge_separation, plan.options.sliver_factor, plan.options.grid,
                       plan.options.max_drift_factor);
    const std::string names = plan.layers.size() > 1 ? layers_label(plan) : "layer '" + output_layer_name(plan, 0) + "'";
    out << fmt::format("output:    {} ({}), {}, FIDs {}\n", plan.write.path, plan.output_driver, names,
                       plan.keeps_fids ? "kept" : "in field orig_fid");
    if (plan.tiling.plan.single)
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
