#include "io/field_fidelity.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace trisnap {
namespace {

constexpr std::size_t k_dbf_max_string = 254; // dBASE's limit; the driver widens fields up to it
constexpr double k_relative_change = 1e-12;

/// What happened to one value: `kind` is counted per field, `detail` goes into the problem.
struct Change {
    std::string kind;
    std::string detail;
};

bool is_integer(OGRFieldType type)
{
    return type == OFTInteger || type == OFTInteger64;
}

bool is_numeric(OGRFieldType type)
{
    return is_integer(type) || type == OFTReal;
}

std::string type_name(OGRFieldType type)
{
    return OGRFieldDefn::GetFieldTypeName(type);
}

bool changed_number(double before, double after)
{
    if (std::isnan(before) || std::isnan(after)) {
        return std::isnan(before) != std::isnan(after);
    }
    return std::fabs(after - before) > k_relative_change * std::fabs(before) || (before != 0.0 && after == 0.0);
}

bool has_time_of_day(const OGRFeature& f, int i)
{
    int y = 0;
    int mo = 0;
    int d = 0;
    int h = 0;
    int mi = 0;
    float s = 0;
    int tz = 0;
    f.GetFieldAsDateTime(i, &y, &mo, &d, &h, &mi, &s, &tz);
    return h != 0 || mi != 0 || s != 0.0f;
}

/// A value converted to another field type that does not read back the same.
Change conversion_change(const OGRFeature& source, int i, const OGRFeature& written, int o)
{
    const OGRFieldType from = source.GetFieldDefnRef(i)->GetType();
    const OGRFieldType to = written.GetFieldDefnRef(o)->GetType();
    if (to == OFTString) {
        return {}; // the text form keeps the value
    }
    if (is_integer(from) && is_integer(to)) {
        if (source.GetFieldAsInteger64(i) == written.GetFieldAsInteger64(o)) {
            return {};
        }
    } else if (is_numeric(from) && is_numeric(to)) {
        if (!changed_number(source.GetFieldAsDouble(i), written.GetFieldAsDouble(o))) {
            return {};
        }
    } else if (from == OFTDateTime && to == OFTDate) {
        if (!has_time_of_day(source, i)) {
            return {};
        }
        return {"stored without its time of day (a Date field)", source.GetFieldAsString(i)};
    } else if (std::string(source.GetFieldAsString(i)) == written.GetFieldAsString(o)) {
        return {};
    }
    // Named only here: every written value passes through this function (a feature's fields,
    // on the writer's thread), and nearly all read back the same.
    return {"changed by the conversion from " + type_name(from) + " to " + type_name(to),
            fmt::format("{} -> {}", source.GetFieldAsString(i), written.GetFieldAsString(o))};
}

/// What a .dbf stores for a Real: printed with the field's width and decimals, cut to the width.
Change dbf_real_change(double value, int width, int decimals)
{
    if (width <= 0) {
        return {};
    }
    std::string text = fmt::format("{:{}.{}f}", value, width, decimals);
    const bool too_wide = text.size() > static_cast<std::size_t>(width);
    text.resize(std::min(text.size(), static_cast<std::size_t>(width)));
    const double stored = std::strtod(text.c_str(), nullptr);
    if (!changed_number(value, stored)) {
        return {};
    }
    const std::string detail = fmt::format("{:.17g} stored as {:.17g}", value, stored);
    if (too_wide) {
        return {fmt::format("too wide for Real({}.{}): cut", width, decimals), detail};
    }
    return {fmt::format("rounded to the {} decimals of Real({}.{})", decimals, width, decimals), detail};
}

Change dbf_date_change(const OGRFeature& written, int o)
{
    const int year = written.GetRawFieldRef(o)->Date.Year;
    if (year >= 0 && year <= 9999) {
        return {};
    }
    return {"not stored: the year is outside 0-9999", written.GetFieldAsString(o)};
}

Change dbf_change_of(const OGRFeature& written, int o)
{
    const OGRFieldDefn& field = *written.GetFieldDefnRef(o);
    switch (field.GetType()) {
    case OFTString: {
        const std::size_t bytes = std::string(written.GetFieldAsString(o)).size();
        if (bytes <= k_dbf_max_string) {
            return {};
        }
        return {"cut to 254 bytes", fmt::format("{} bytes", bytes)};
    }
    case OFTReal:
        return dbf_real_change(written.GetFieldAsDouble(o), field.GetWidth(), field.GetPrecision());
    case OFTDate:
    case OFTDateTime:
        return dbf_date_change(written, o);
    default:
        return {};
    }
}

Problem field_problem(std::int64_t fid, ProblemCode code, std::string message)
{
    Problem p;
    p.feature_id = fid;
    p.code = code;
    p.message = std::move(message);
    p.x = std::numeric_limits<double>::quiet_NaN();
    p.y = p.x;
    return p;
}

} // namespace

FieldFidelity::FieldFidelity(const OGRFeatureDefn& input, const OGRFeatureDefn& output,
                             const std::vector<int>& field_map, const std::string& driver)
    : m_field_map(field_map), m_dbf(driver == "ESRI Shapefile")
{
    for (std::size_t i = 0; i < field_map.size(); ++i) {
        const std::string from = input.GetFieldDefn(static_cast<int>(i))->GetNameRef();
        m_names.push_back(from);
        if (field_map[i] < 0) {
            continue; // not selected (--select): not written
        }
        const std::string to = output.GetFieldDefn(field_map[i])->GetNameRef();
        if (from != to) {
            m_renamed.push_back(field_problem(-1, ProblemCode::field_renamed,
                                              "field '" + from + "' is named '" + to + "' in the output"));
        }
    }
}

void FieldFidelity::check(const OGRFeature& source, const OGRFeature& written, std::int64_t fid,
                          std::vector<Problem>& out)
{
    for (std::size_t i = 0; i < m_field_map.size(); ++i) {
        const int in = static_cast<int>(i);
        if (m_field_map[i] < 0 || !source.IsFieldSetAndNotNull(in)) {
            continue;
        }
        Change change = written.IsFieldSetAndNotNull(m_field_map[i])
                            ? conversion_change(source, in, written, m_field_map[i])
                            : Change{"written as null", source.GetFieldAsString(in)};
        if (change.kind.empty() && m_dbf) {
            change = dbf_change_of(written, m_field_map[i]);
        }
        if (change.kind.empty()) {
            continue;
        }
        const std::string& name = m_names[i];
        out.push_back(field_problem(fid, ProblemCode::value_changed,
                                    "field '" + name + "': value " + change.kind + " (" + change.detail + ")"));
        Tally& tally = m_tallies[{name, change.kind}];
        if (tally.count++ == 0) {
            tally.first_fid = fid;
        }
    }
}

std::vector<std::string> FieldFidelity::summary() const
{
    std::vector<std::string> lines;
    for (const auto& [key, tally] : m_tallies) {
        lines.push_back(fmt::format("field '{}': {} value{} {} (first FID {}; problem 903)", key.first, tally.count,
                                    tally.count == 1 ? "" : "s", key.second, tally.first_fid));
    }
    for (const Problem& p : m_renamed) {
        lines.push_back(p.message + " (problem 904)");
    }
    return lines;
}

} // namespace trisnap
