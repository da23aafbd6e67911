#pragma once
// One golden case: tests/cases/<name>/ holds
//   input.wkt              `id;WKT` per line (the engine's feature file format)
//   tolerance.txt          t, one number ('#' comment lines allowed)
//   expected.wkt           `id;WKT` per output feature, in input order (EMPTY when collapsed)
//   expected_problems.txt  `id code` per reported problem, sorted
// Comparison is on normalised geometry: the engine writes canonical ring starts and orders,
// so two outputs match when their structure is equal and every coordinate is within
// 1e-9 x scale (scale = the input's extent).
#include "core/geometry.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace trisnap {

struct GoldenCase {
    std::string name;
    std::filesystem::path dir;
    std::vector<Feature> input;
    double tolerance = 0.0;
    std::vector<Feature> expected;    ///< empty when expected.wkt does not exist yet
    std::string expected_problems;    ///< "id code\n" lines
    bool has_expected = false;
};

/// The case directories under `root` that hold an input.wkt, sorted by name.
std::vector<std::string> golden_case_names(const std::filesystem::path& root);

/// Reads one case; throws std::runtime_error naming the file on a missing or bad file.
GoldenCase read_golden_case(const std::filesystem::path& root, const std::string& name);

/// Writes expected.wkt and expected_problems.txt (TRISNAP_UPDATE_GOLDEN=1 mode).
void write_golden_expected(const GoldenCase& c, const std::vector<Feature>& output,
                           const std::string& problems);

/// Largest extent of the input's bounding box (1 when it is a point or empty).
double input_scale(const std::vector<Feature>& features);

/// "" when `actual` matches `expected` (same ids in the same order, same types and structure,
/// coordinates within abs_tol, Z within abs_tol when present); else the first difference.
std::string geometry_difference(const std::vector<Feature>& expected,
                                const std::vector<Feature>& actual, double abs_tol);

} // namespace trisnap
