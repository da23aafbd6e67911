#include "assess/snap_report.hpp"

#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <fstream>

namespace trisnap::assess {
namespace {

using nlohmann::json;

std::optional<Pt> location(const json& p)
{
    const json x = p.value("x", json());
    const json y = p.value("y", json());
    if (!x.is_number() || !y.is_number()) {
        return std::nullopt;
    }
    return Pt{x.get<double>(), y.get<double>()};
}

ReportedProblem problem_of(const json& p)
{
    ReportedProblem problem;
    problem.fid = p.value("fid", std::int64_t{-1});
    problem.code = p.value("code", 0);
    problem.name = p.value("name", std::string());
    problem.at = location(p);
    return problem;
}

json parse(const std::string& path)
{
    std::ifstream file(path);
    if (!file) {
        throw io_error(path, "", "cannot open the report");
    }
    try {
        return json::parse(file);
    } catch (const json::exception& e) {
        throw io_error(path, "", std::string("not a JSON report: ") + e.what());
    }
}

} // namespace

SnapReport read_snap_report(const std::string& path)
{
    const json report = parse(path);
    if (!report.is_object() || !report.contains("problems") || !report["problems"].is_array()) {
        throw io_error(path, "", "no 'problems' list: not a `trisnap snap --report` file");
    }
    SnapReport out;
    out.path = path;
    const json t = report.value("/config/tolerance_layer_units"_json_pointer, json());
    if (t.is_number() && t.get<double>() > 0) {
        out.tolerance = t.get<double>();
    }
    const json n = report.value("/counts/input"_json_pointer, json());
    if (n.is_number_integer()) {
        out.input_features = n.get<std::int64_t>();
    }
    for (const json& p : report["problems"]) {
        if (p.is_object()) {
            out.problems.push_back(problem_of(p));
        }
    }
    return out;
}

} // namespace trisnap::assess
