#pragma once
// Which defects a `trisnap snap --report` explains, per feature and by problem code (README,
// "trisnap assess", lists the table). Conservative: a code excuses only what it says happened.
//  - missing (no output feature): 106 non_finite_coordinate, 107 empty_geometry (nothing usable
//    remained), 108 unsupported_geometry (rejected), 109 huge_coordinate, 201 collapsed_polygon,
//    202 collapsed_line, 901 unreadable_feature, 902 unwritable_feature;
//  - drift (Hausdorff > 2T) of that feature: 103 degenerate_ring and 104 degenerate_line
//    (dropped), 105 self_intersection (repaired odd-even), 203 part_removed, 204 hole_removed,
//    206 drift_exceeded, 208 topology_changed, 209 thin_part_collapsed;
//  - a new gap between two features: 203, 204, 208, 209 or 210 shared_boundary_lost on either;
//  - a separation breach (vertex-vertex < T, vertex-edge < T/2): a 205 not_converged or 207
//    separation_not_reached problem located within T of either end of the pair.
// Invalid polygons, new overlaps and new crossings are never excused: no code explains them.
#include "assess/geometry.hpp"
#include "assess/snap_report.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace trisnap::assess {

enum class Defect { missing, drift, gap };

class Excuses {
public:
    Excuses() = default; // excuses nothing
    explicit Excuses(const SnapReport& report);

    /// The codes of feature `fid` that explain `defect`, as "204 hole_removed, 209
    /// thin_part_collapsed"; empty when none does.
    std::string explain(Defect defect, std::int64_t fid) const;
    /// The same for a defect of a pair of features (either may explain it).
    std::string explain(Defect defect, std::int64_t fid_a, std::int64_t fid_b) const;
    /// Located 205/207 problems within `radius` of p or q, as above.
    std::string explain_separation(Pt p, Pt q, double radius) const;

private:
    struct Entry {
        std::int64_t fid;
        int code;
        std::string name;
    };
    std::vector<Entry> m_by_fid;           // sorted by fid, then code
    std::vector<ReportedProblem> m_located; // 205 and 207 with a place
};

} // namespace trisnap::assess
