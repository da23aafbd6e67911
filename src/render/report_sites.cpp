// Problems from a `trisnap snap --report` file, as sites to mark.
#include "render/sites.hpp"

#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <fstream>

namespace trisnap::render {

std::vector<Site> read_problem_sites(const std::string& path, std::optional<double>& tolerance)
{
    std::ifstream file(path);
    if (!file) throw io_error(path, "", "cannot open the report");
    nlohmann::json report;
    try {
        report = nlohmann::json::parse(file);
    } catch (const nlohmann::json::exception& e) {
        throw io_error(path, "", std::string("not a JSON report: ") + e.what());
    }
    if (!report.is_object() || !report.contains("problems") || !report["problems"].is_array())
        throw io_error(path, "", "no 'problems' list: not a `trisnap snap --report` file");
    const auto t = report.value("/config/tolerance_layer_units"_json_pointer, nlohmann::json());
    if (t.is_number() && t.get<double>() > 0) tolerance = t.get<double>();
    std::vector<Site> sites;
    for (const auto& p : report["problems"]) {
        if (!p.is_object() || !p.contains("x") || !p["x"].is_number() || !p.contains("y") || !p["y"].is_number())
            continue;
        Site site;
        site.kind = SiteKind::problem;
        site.at = site.other = {p["x"].get<double>(), p["y"].get<double>()};
        site.fid = p.value("fid", std::int64_t{-1});
        site.code = p.value("code", 0);
        site.name = p.value("name", std::string());
        site.defect = true;
        sites.push_back(site);
    }
    return sites;
}

} // namespace trisnap::render
