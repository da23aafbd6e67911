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
    for (const AssessExample& e : examples) {
        out.push_back(one(e));
    }
    return out;
}

json pair_at(const AssessExample& e) { return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"x", e.x}, {"y", e.y}}; }

json excused_by(const AssessExample& e) { return e.excused_by.empty() ? json(nullptr) : json(e.excused_by); }

json defect_examples(const AssessReport& r)
{
    json ex;
    ex["invalid"] = list(r.invalid, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"x", e.x}, {"y", e.y}, {"reason", e.text}};
    });
    ex["empty"] = list(r.empty, [](const AssessExample& e) -> json { return {{"fid", e.fid_a}}; });
    ex["unmeasurable"] = list(r.unmeasurable, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a >= 0 ? e.fid_a : e.fid_b}, {"layer", e.text}};
    });
    ex["overlaps"] = list(r.overlaps, [](const AssessExample& e) -> json {
        json j = pair_at(e);
        j["area"] = e.value;
        j["new"] = e.is_new;
        return j;
    });
    ex["gaps_new"] = list(r.gaps_new_examples, [](const AssessExample& e) -> json {
        json j = pair_at(e);
        j["shared_length_in"] = e.value;
        j["excused_by"] = excused_by(e);
        return j;
    });
    ex["crossings"] = list(r.crossings, [](const AssessExample& e) -> json {
        json j = pair_at(e);
        j["new"] = e.is_new;
        return j;
    });
    ex["missing"] = list(r.missing, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"x", e.x}, {"y", e.y}, {"size", e.value}, {"reason", e.text}, {"excused_by", excused_by(e)}};
    });
    ex["extra"] = list(r.extra, [](const AssessExample& e) -> json { return {{"fid", e.fid_b}, {"x", e.x}, {"y", e.y}}; });
    ex["attr_mismatch"] = list(r.attr_mismatch, [](const AssessExample& e) -> json {
        return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"difference", e.text}};
    });
    return ex;
}

json extreme_examples(const AssessReport& r)
{
    json ex;
    ex["closest_vertex_edge"] = list(r.closest_vertex_edge, [](const AssessExample& e) -> json {
        return {{"fid_vertex", e.fid_a}, {"fid_edge", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y},
                {"closest_x", e.x2}, {"closest_y", e.y2}, {"edge", {e.edge[0], e.edge[1], e.edge[2], e.edge[3]}},
                {"excused_by", excused_by(e)}};
    });
    ex["closest_vertex_vertex"] = list(r.closest_vertex_vertex, [](const AssessExample& e) -> json {
        return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y},
                {"x2", e.x2}, {"y2", e.y2}, {"excused_by", excused_by(e)}};
    });
    ex["largest_hausdorff"] = list(r.largest_hausdorff, [](const AssessExample& e) -> json {
        return {{"fid", e.fid_a}, {"fid_out", e.fid_b}, {"distance", e.value}, {"x", e.x}, {"y", e.y},
                {"nearest_x", e.x2}, {"nearest_y", e.y2}, {"excused_by", excused_by(e)}};
    });
    ex["excused"] = list(r.excused, [](const AssessExample& e) -> json {
        return {{"fid_a", e.fid_a}, {"fid_b", e.fid_b}, {"what", e.text}, {"value", e.value}, {"x", e.x}, {"y", e.y},
                {"excused_by", e.excused_by}};
    });
    return ex;
}

json sites_json(const std::vector<assess::Site>& sites, double t)
{
    json out = json::array();
    for (std::size_t i = 0; i < sites.size(); ++i) {
        const assess::Site& s = sites[i];
        out.push_back({{"rank", i + 1}, {"kind", assess::site_kind_name(s.kind)}, {"code", s.code}, {"value", s.value},
                       {"value_over_t", s.value / t}, {"fid", s.fid}, {"fid_b", s.fid2}, {"x", s.at.x}, {"y", s.at.y},
                       {"breach", s.breach}, {"excused_by", s.excused_by.empty() ? json(nullptr) : json(s.excused_by)}});
    }
    return out;
}

void add_counts(const AssessReport& r, json& j)
{
    const std::pair<const char*, std::int64_t> counts[] = {
        {"n_in", r.n_in}, {"n_out", r.n_out}, {"n_matched", r.n_matched}, {"n_missing", r.n_missing},
        {"n_extra", r.n_extra}, {"n_attr_mismatch", r.n_attr_mismatch}, {"n_invalid", r.n_invalid},
        {"n_empty", r.n_empty}, {"n_unmeasurable", r.n_unmeasurable}, {"n_overlaps", r.n_overlaps},
        {"n_overlaps_new", r.n_overlaps_new}, {"n_shared_in", r.n_shared_in}, {"gaps_new", r.gaps_new},
        {"n_crossings", r.n_crossings}, {"n_crossings_new", r.n_crossings_new}, {"n_vv_breaches", r.n_vv_breaches},
        {"n_ve_breaches", r.n_ve_breaches}, {"n_drift", r.n_drift}};
    for (const auto& [key, value] : counts) {
        j[key] = value;
    }
    const ExcusedCounts& e = r.excused_counts;
    j["excused"] = {{"missing", e.missing}, {"drift", e.drift}, {"gaps", e.gaps}, {"separations", e.separations},
                    {"total", e.total()}};
}

void add_measures(const AssessReport& r, json& j)
{
    const double t = r.tolerance;
    j["overlap_area"] = r.overlap_area;
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
}

} // namespace

std::string assess_report_json(const AssessReport& r)
{
    json j;
    j["layer_a"] = r.layer_a;
    j["layer_b"] = r.layer_b;
    j["matched_by"] = r.matched_by;
    j["snap_report"] = r.snap_report.empty() ? json(nullptr) : json(r.snap_report);
    j["tolerance"] = r.tolerance;
    add_counts(r, j);
    add_measures(r, j);
    j["contract_holds"] = r.contract_holds();
    j["contract_failures"] = r.contract_failures();
    j["worst_sites"] = sites_json(r.worst, r.tolerance);
    j["seconds"] = r.seconds;
    j["timings"] = json::object();
    for (const auto& [name, seconds] : r.timings) {
        j["timings"][name] = seconds;
    }
    j["examples"] = defect_examples(r);
    j["examples"].update(extreme_examples(r));
    return j.dump(2) + "\n";
}

} // namespace trisnap
