// The report as JSON (stable keys: other tools read them) and as a table for people.
#include "assess/assess.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace trisnap {
namespace {

using nlohmann::json;

json optional_number(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json ratio(const std::optional<double>& v, double t) { return v ? json(*v / t) : json(nullptr); }

json list(const std::vector<AssessExample>& examples, json (*one)(const AssessExample&))
{
    json out = json::array();
    for (const AssessExample& e : examples) out.push_back(one(e));
    return out;
}

json pair_at(const AssessExample& e) { return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"x", e.x}, {"y", e.y}}; }

json examples(const AssessReport& r)
{
    json ex;
    ex["invalid"] = list(r.invalid, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"x", e.x}, {"y", e.y}, {"reason", e.text}};
    });
    ex["empty"] = list(r.empty, [](const AssessExample& e) -> json { return {{"fid", e.fid_a}}; });
    ex["overlaps"] = list(r.overlaps, [](const AssessExample& e) -> json {
        json j = pair_at(e);
        j["area"] = e.value;
        j["new"] = e.text == "new";
        return j;
    });
    ex["gaps_new"] = list(r.gaps_new_examples, [](const AssessExample& e) -> json {
        json j = pair_at(e);
        j["shared_length_in"] = e.value;
        return j;
    });
    ex["crossings"] = list(r.crossings, pair_at);
    ex["closest_vertex_edge"] = list(r.closest_vertex_edge, [](const AssessExample& e) -> json {
        return {{"fid_vertex", e.fid_a}, {"fid_edge", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y},
                {"closest_x", e.x2}, {"closest_y", e.y2}, {"edge", {e.edge[0], e.edge[1], e.edge[2], e.edge[3]}}};
    });
    ex["closest_vertex_vertex"] = list(r.closest_vertex_vertex, [](const AssessExample& e) -> json {
        return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y},
                {"x2", e.x2}, {"y2", e.y2}};
    });
    ex["largest_hausdorff"] = list(r.largest_hausdorff, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"fid_out", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y}};
    });
    ex["missing"] = list(r.missing, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"x", e.x}, {"y", e.y}, {"reason", e.text}};
    });
    ex["extra"] = list(r.extra, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_b}, {"x", e.x}, {"y", e.y}};
    });
    ex["attr_mismatch"] = list(r.attr_mismatch, [](const AssessExample& e) -> json {
        return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"difference", e.text}};
    });
    return ex;
}

} // namespace

std::string assess_report_json(const AssessReport& r)
{
    const double t = r.tolerance;
    json j;
    j["layer_a"] = r.layer_a;
    j["layer_b"] = r.layer_b;
    j["matched_by"] = r.matched_by;
    j["tolerance"] = t;
    j["n_in"] = r.n_in;
    j["n_out"] = r.n_out;
    j["n_matched"] = r.n_matched;
    j["n_missing"] = r.n_missing;
    j["n_extra"] = r.n_extra;
    j["n_attr_mismatch"] = r.n_attr_mismatch;
    j["n_invalid"] = r.n_invalid;
    j["n_empty"] = r.n_empty;
    j["n_overlaps"] = r.n_overlaps;
    j["overlap_area"] = r.overlap_area;
    j["n_overlaps_new"] = r.n_overlaps_new;
    j["n_shared_in"] = r.n_shared_in;
    j["gaps_new"] = r.gaps_new;
    j["n_crossings"] = r.n_crossings;
    j["min_vertex_vertex"] = optional_number(r.min_vertex_vertex);
    j["min_vertex_edge"] = optional_number(r.min_vertex_edge);
    j["max_hausdorff"] = r.max_hausdorff;
    j["p99_hausdorff"] = r.p99_hausdorff;
    j["area_in"] = r.area_in;
    j["area_out"] = r.area_out;
    j["area_change"] = r.area_change;
    j["min_vertex_vertex_over_t"] = ratio(r.min_vertex_vertex, t);
    j["min_vertex_edge_over_t"] = ratio(r.min_vertex_edge, t);
    j["max_hausdorff_over_t"] = r.max_hausdorff / t;
    j["contract_holds"] = r.contract_holds();
    j["contract_failures"] = r.contract_failures();
    j["seconds"] = r.seconds;
    j["timings"] = json::object();
    for (const auto& [name, seconds] : r.timings) j["timings"][name] = seconds;
    j["examples"] = examples(r);
    return j.dump(2) + "\n";
}

std::string assess_report_table(const AssessReport& r)
{
    const double t = r.tolerance;
    const auto sep = [&](const std::optional<double>& v) {
        return v ? fmt::format("{:.6g} ({:.3g} T)", *v, *v / t) : std::string("none");
    };
    std::string out = fmt::format("assess '{}' -> '{}', tolerance T = {:g}\n", r.layer_a, r.layer_b, t);
    const auto row = [&](const char* name, const std::string& value) { out += fmt::format("  {:<22}{}\n", name, value); };
    row("features", fmt::format("{} in, {} out, {} matched by {}", r.n_in, r.n_out, r.n_matched, r.matched_by));
    row("missing / extra", fmt::format("{} / {}", r.n_missing, r.n_extra));
    row("attribute mismatches", std::to_string(r.n_attr_mismatch));
    row("empty outputs", std::to_string(r.n_empty));
    row("invalid polygons", std::to_string(r.n_invalid));
    row("overlapping pairs", fmt::format("{} (area {:.6g}), {} new", r.n_overlaps, r.overlap_area, r.n_overlaps_new));
    row("new gaps", fmt::format("{} of {} shared boundaries", r.gaps_new, r.n_shared_in));
    row("crossings", std::to_string(r.n_crossings));
    row("min vertex-vertex", sep(r.min_vertex_vertex) + "  (contract >= T)");
    row("min vertex-edge", sep(r.min_vertex_edge) + "  (contract >= T/2)");
    row("max Hausdorff", fmt::format("{:.6g} ({:.3g} T)  (contract <= 2T)", r.max_hausdorff, r.max_hausdorff / t));
    row("p99 Hausdorff", fmt::format("{:.6g} ({:.3g} T)", r.p99_hausdorff, r.p99_hausdorff / t));
    row("area change", fmt::format("{:+.3g} %", 100 * r.area_change));
    const std::vector<std::string> failures = r.contract_failures();
    std::string verdict = failures.empty() ? "holds" : "does NOT hold:";
    for (const std::string& f : failures) verdict += " " + f + ";";
    row("contract", verdict);
    std::string phases;
    for (const auto& [name, seconds] : r.timings) phases += fmt::format("{}{} {:.2f}", phases.empty() ? "" : ", ", name, seconds);
    row("time", fmt::format("{:.2f} s ({})", r.seconds, phases));
    return out;
}

} // namespace trisnap
