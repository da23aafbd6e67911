#include "io/problems_layer.hpp"

#include "config/errors.hpp"
#include "io/gdal_errors.hpp"
#include "io/io_error.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

constexpr const char* k_layer = "problems";

/// "GPKG" or "GeoJSON" from the extension, "" for anything else.
std::string driver_for(const std::string& path)
{
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".gpkg") {
        return "GPKG";
    }
    return ext == ".geojson" || ext == ".json" ? "GeoJSON" : "";
}

/// `layers` not empty (several input layers): a field "layer" after "fid" names each FID's layer.
void create_fields(OGRLayer& layer, const std::string& path, const std::vector<std::string>& layers)
{
    std::vector<std::pair<const char*, OGRFieldType>> fields = {
        {"fid", OFTInteger64}, {"code", OFTInteger}, {"name", OFTString}, {"message", OFTString}};
    if (!layers.empty()) {
        fields.insert(fields.begin() + 1, {"layer", OFTString});
    }
    for (const auto& [name, type] : fields) {
        OGRFieldDefn field(name, type);
        if (layer.CreateField(&field) != OGRERR_NONE) {
            throw io_error(path, "problems", std::string("cannot create field ") + name);
        }
    }
}

void write_problem(OGRLayer& layer, const Problem& problem, const std::string& path, const std::vector<std::string>& layers)
{
    OGRFeatureUniquePtr feature(OGRFeature::CreateFeature(layer.GetLayerDefn()));
    feature->SetField("fid", static_cast<GIntBig>(problem.feature_id));
    if (!layers.empty()) {
        feature->SetField("layer", layers.at(problem.layer).c_str());
    }
    feature->SetField("code", static_cast<int>(problem.code));
    feature->SetField("name", problem_name(problem.code));
    feature->SetField("message", problem.message.c_str());
    if (std::isfinite(problem.x) && std::isfinite(problem.y)) {
        feature->SetGeometryDirectly(new OGRPoint(problem.x, problem.y));
    }
    if (layer.CreateFeature(feature.get()) != OGRERR_NONE) {
        throw io_error(path, "problems", "cannot write the problem of FID " + std::to_string(problem.feature_id));
    }
}

/// Layer "problems" in `dataset`; GPKG keeps its own FID column out of the way of our "fid" field.
void fill_dataset(GDALDataset& dataset, const std::string& path, const ProblemSource& problems,
                  OGRSpatialReference* srs, const std::vector<std::string>& layers)
{
    ScopedErrorCapture capture;
    CPLStringList options;
    if (std::string(dataset.GetDriver()->GetDescription()) == "GPKG") {
        options.AddString("FID=problem_id");
    }
    OGRLayer* layer = dataset.CreateLayer(k_layer, srs, wkbPoint, options.List());
    if (!layer) {
        throw io_error(path, k_layer, capture.last_error("cannot create the layer"));
    }
    create_fields(*layer, path, layers);
    problems([&](const Problem& problem) { write_problem(*layer, problem, path, layers); });
}

/// A new file at `temp`, in one transaction.
void write_dataset(const std::string& temp, const std::string& path, const ProblemSource& problems,
                   OGRSpatialReference* srs, const std::vector<std::string>& layers)
{
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_for(path).c_str());
    ScopedErrorCapture capture;
    GDALDatasetUniquePtr dataset(driver ? driver->Create(temp.c_str(), 0, 0, 0, GDT_Unknown, nullptr) : nullptr);
    if (!dataset) {
        throw io_error(path, "", capture.last_error("cannot create the dataset"));
    }
    dataset->StartTransaction();
    fill_dataset(*dataset, path, problems, srs, layers);
    dataset->CommitTransaction();
    dataset.reset();
    if (!capture.errors().empty()) {
        throw io_error(path, k_layer, capture.last_error());
    }
}

/// An existing GeoPackage: its layer "problems" replaced (or added) in one transaction, its
/// other layers kept; any failure rolls the transaction back.
void update_dataset(const std::string& path, const ProblemSource& problems, OGRSpatialReference* srs,
                    const std::vector<std::string>& layers)
{
    const char* const drivers[] = {"GPKG", nullptr};
    ScopedErrorCapture capture;
    GDALDatasetUniquePtr dataset(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, drivers, nullptr, nullptr));
    if (!dataset || dataset->StartTransaction() != OGRERR_NONE) {
        throw io_error(path, "", capture.last_error("cannot open it for update"));
    }
    try {
        for (int i = 0; i < dataset->GetLayerCount(); ++i) {
            if (std::string(dataset->GetLayer(i)->GetName()) == k_layer && dataset->DeleteLayer(i) != OGRERR_NONE) {
                throw io_error(path, k_layer, capture.last_error("cannot delete the layer to replace it"));
            }
        }
        fill_dataset(*dataset, path, problems, srs, layers);
        if (dataset->CommitTransaction() != OGRERR_NONE) {
            throw io_error(path, k_layer, capture.last_error("cannot commit"));
        }
    } catch (...) {
        dataset->RollbackTransaction();
        throw;
    }
}

bool updates_gpkg(const std::string& path, bool update)
{
    std::error_code ec;
    return update && driver_for(path) == "GPKG" && fs::exists(path, ec);
}

/// True when the GeoPackage at `path` has a layer "problems".
bool has_problems_layer(const std::string& path)
{
    ScopedErrorCapture quiet;
    GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    return dataset && dataset->GetLayerByName(k_layer) != nullptr;
}

} // namespace

void check_problems_layer_path(const std::string& path, bool overwrite, bool update)
{
    if (driver_for(path).empty()) {
        throw argument_error("--problems-layer " + path + ": give a .gpkg or .geojson file name");
    }
    std::error_code ec;
    if (updates_gpkg(path, update || overwrite)) {
        if (!overwrite && has_problems_layer(path)) {
            throw argument_error("--problems-layer " + path +
                                 ": has a layer 'problems' already; add --overwrite to replace it");
        }
        return;
    }
    if (fs::exists(path, ec) && !overwrite) {
        throw argument_error("--problems-layer " + path + ": already exists; add --overwrite to replace it");
    }
    const fs::path p(path);
    const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec)) {
        throw argument_error("--problems-layer " + path + ": the directory " + parent.string() + " does not exist");
    }
}

void write_problems_layer(const std::string& path, const std::vector<Problem>& problems,
                          OGRSpatialReference* srs, bool update, const std::vector<std::string>& layers)
{
    const ProblemSource source = [&](const std::function<void(const Problem&)>& f) {
        std::for_each(problems.begin(), problems.end(), f);
    };
    write_problems_layer(path, source, srs, update, layers);
}

void write_problems_layer(const std::string& path, const ProblemSource& problems, OGRSpatialReference* srs,
                          bool update, const std::vector<std::string>& layers)
{
    if (updates_gpkg(path, update)) {
        update_dataset(path, problems, srs, layers);
        return;
    }
    const fs::path target(path);
    std::string name = ".";
    name.append(target.filename().string()).append(".trisnap-tmp-").append(std::to_string(getpid()));
    const fs::path temp = target.parent_path() / name.append(target.extension().string());
    std::error_code ec;
    try {
        write_dataset(temp.string(), path, problems, srs, layers);
    } catch (...) {
        fs::remove(temp, ec);
        throw;
    }
    fs::rename(temp, target, ec);
    if (ec) {
        fs::remove(temp, ec);
        throw io_error(path, "", "cannot move the problems layer into place: " + ec.message());
    }
}

} // namespace trisnap
