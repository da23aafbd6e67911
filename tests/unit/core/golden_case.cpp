#include "golden_case.hpp"

#include "core/wkt.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace trisnap {
namespace fs = std::filesystem;
namespace {

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    if (!in)
        throw std::runtime_error(path.string() + ": cannot open");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<Feature> read_features(const fs::path& path) {
    std::ifstream in(path);
    if (!in)
        throw std::runtime_error(path.string() + ": cannot open");
    try {
        return read_wkt_features(in);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(path.string() + ": " + e.what());
    }
}

double read_tolerance(const fs::path& path) {
    std::istringstream lines(read_text(path));
    std::string line;
    while (std::getline(lines, line)) {
        if (line.empty() || line[0] == '#')
            continue;
        return std::stod(line);
    }
    throw std::runtime_error(path.string() + ": no tolerance");
}

/// Every coordinate of a geometry, in writing order, with a structure signature on the side.
void flatten(const Geometry& g, std::vector<Coord>& coords, std::string& shape) {
    shape += std::to_string(static_cast<int>(g.type)) + (g.has_z ? "z" : "") + ":";
    auto add_path = [&](const Path& p) {
        shape += std::to_string(p.size()) + ",";
        coords.insert(coords.end(), p.begin(), p.end());
    };
    for (const Polygon& p : g.polygons) {
        shape += "(";
        std::for_each(p.rings.begin(), p.rings.end(), add_path);
        shape += ")";
    }
    std::for_each(g.lines.begin(), g.lines.end(), add_path);
}

bool z_close(double a, double b, double tol) {
    if (std::isnan(a) || std::isnan(b))
        return std::isnan(a) == std::isnan(b);
    return std::abs(a - b) <= tol;
}

std::string feature_difference(const Feature& e, const Feature& a, double tol) {
    std::vector<Coord> ce, ca;
    std::string se, sa;
    flatten(e.geometry, ce, se);
    flatten(a.geometry, ca, sa);
    const std::string where = "id " + std::to_string(e.id) + ": ";
    if (se != sa)
        return where + "structure differs:\n  expected " + to_wkt(e.geometry) + "\n  actual   " +
               to_wkt(a.geometry);
    for (std::size_t i = 0; i < ce.size(); ++i) {
        if (std::abs(ce[i].x - ca[i].x) > tol || std::abs(ce[i].y - ca[i].y) > tol ||
            !z_close(ce[i].z, ca[i].z, tol))
            return where + "coordinate " + std::to_string(i) + " differs:\n  expected " +
                   to_wkt(e.geometry) + "\n  actual   " + to_wkt(a.geometry);
    }
    return {};
}

} // namespace

std::vector<std::string> golden_case_names(const fs::path& root) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(root, ec))
        if (entry.is_directory() && fs::exists(entry.path() / "input.wkt"))
            names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

GoldenCase read_golden_case(const fs::path& root, const std::string& name) {
    GoldenCase c;
    c.name = name;
    c.dir = root / name;
    c.input = read_features(c.dir / "input.wkt");
    c.tolerance = read_tolerance(c.dir / "tolerance.txt");
    c.has_expected = fs::exists(c.dir / "expected.wkt");
    if (c.has_expected) {
        c.expected = read_features(c.dir / "expected.wkt");
        if (fs::exists(c.dir / "expected_problems.txt"))
            c.expected_problems = read_text(c.dir / "expected_problems.txt");
    }
    return c;
}

void write_golden_expected(const GoldenCase& c, const std::vector<Feature>& output,
                           const std::string& problems) {
    std::ofstream wkt(c.dir / "expected.wkt");
    for (const Feature& f : output)
        wkt << f.id << ';' << to_wkt(f.geometry) << '\n';
    std::ofstream(c.dir / "expected_problems.txt") << problems;
}

double input_scale(const std::vector<Feature>& features) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    auto visit = [&](const Coord& p) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            return;
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
        y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    };
    for (const Feature& f : features) {
        for (const Polygon& p : f.geometry.polygons)
            for (const Path& r : p.rings)
                std::for_each(r.begin(), r.end(), visit);
        for (const Path& l : f.geometry.lines)
            std::for_each(l.begin(), l.end(), visit);
    }
    const double extent = std::max(x1 - x0, y1 - y0);
    return std::isfinite(extent) && extent > 0 ? extent : 1.0;
}

std::string geometry_difference(const std::vector<Feature>& expected,
                                const std::vector<Feature>& actual, double abs_tol) {
    if (expected.size() != actual.size())
        return "expected " + std::to_string(expected.size()) + " features, got " +
               std::to_string(actual.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (expected[i].id != actual[i].id)
            return "feature " + std::to_string(i) + ": expected id " +
                   std::to_string(expected[i].id) + ", got " + std::to_string(actual[i].id);
        if (std::string d = feature_difference(expected[i], actual[i], abs_tol); !d.empty())
            return d;
    }
    return {};
}

} // namespace trisnap
