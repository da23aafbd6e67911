#include "config/size.hpp"

#include "config/errors.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>

namespace trisnap {
namespace {

double unit_factor(std::string unit)
{
    for (char& c : unit) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    constexpr double k = 1024.0;
    if (unit.empty() || unit == "b") {
        return 1;
    }
    if (unit == "k" || unit == "kib") {
        return k;
    }
    if (unit == "m" || unit == "mib") {
        return k * k;
    }
    if (unit == "g" || unit == "gib") {
        return k * k * k;
    }
    if (unit == "t" || unit == "tib") {
        return k * k * k * k;
    }
    if (unit == "kb") {
        return 1e3;
    }
    if (unit == "mb") {
        return 1e6;
    }
    if (unit == "gb") {
        return 1e9;
    }
    if (unit == "tb") {
        return 1e12;
    }
    return -1;
}

} // namespace

std::uint64_t parse_size(const std::string& text, const std::string& what)
{
    std::size_t end = 0;
    double value = 0;
    try {
        value = std::stod(text, &end);
    } catch (const std::exception&) {
        end = 0;
    }
    std::string unit = text.substr(end);
    while (!unit.empty() && unit.front() == ' ') {
        unit.erase(0, 1);
    }
    const double factor = end == 0 ? -1 : unit_factor(unit);
    const double bytes = value * factor;
    if (factor < 0 || !std::isfinite(bytes) || bytes < 1 || bytes > 1e18) {
        throw argument_error(what + " '" + text + "': expected a size such as 2GiB, 512MiB or 800MB");
    }
    return static_cast<std::uint64_t>(bytes);
}

std::string format_size(std::uint64_t bytes)
{
    const double b = static_cast<double>(bytes);
    if (b >= 1024.0 * 1024 * 1024) {
        return fmt::format("{:.2f} GiB", b / (1024.0 * 1024 * 1024));
    }
    if (b >= 1024.0 * 1024) {
        return fmt::format("{:.0f} MiB", b / (1024.0 * 1024));
    }
    return fmt::format("{:.0f} KiB", b / 1024.0);
}

} // namespace trisnap
