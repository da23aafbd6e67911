#pragma once
// The measurements of the contract checker, one per file, and the example collector they share.
#include "checker_geos.hpp"
#include "contract_checker.hpp"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace trisnap::checker_detail {

/// Keeps at most a few example lines per kind of defect, so one systematic bug does not hide
/// the others in a capped list.
class Examples {
public:
    explicit Examples(std::vector<std::string>& lines) : m_lines(lines) {}
    void add(const std::string& kind, const std::string& line);

private:
    static constexpr std::size_t per_kind = 4;
    std::vector<std::string>& m_lines;
    std::map<std::string, std::size_t> m_counts;
};

std::string point_text(double x, double y);
/// "0.3t (3e-07)": a distance in units of t and in layer units.
std::string distance_text(double d, double t);

/// min_vertex_vertex and min_vertex_edge over the output, with their counts and examples.
void measure_spacing(const Side& out, double t, double edge_factor, ContractReport& report,
                     Examples& examples);

/// max_hausdorff over ids present in both sides.
void measure_hausdorff(const Side& in, const Side& out, double t,
                       const std::vector<std::int64_t>& exempt, ContractReport& report,
                       Examples& examples);

/// n_overlaps_new(_reported) and n_shared_lost(_reported).
void check_pairs(GeosContext& ctx, const Side& in, const Side& out, double t,
                 const std::vector<std::int64_t>& exempt, const std::vector<std::int64_t>& lost_reported,
                 const std::vector<std::int64_t>& unfinished, ContractReport& report, Examples& examples);

} // namespace trisnap::checker_detail
