// Validity (GDAL's IsValid, i.e. GEOS through OGR), empty outputs, and total areas.
// GEOS states why a geometry is invalid as a notice ("Self-intersection at or near point X Y"),
// which GDAL passes on as a CPL warning: a per-thread handler catches it for the example.
#include "assess/measures.hpp"

#include <ogr_geometry.h>
#include <cpl_error.h>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cstdio>
#include <memory>

namespace trisnap::assess {
namespace {

struct Messages {
    std::string last;
};

void CPL_STDCALL remember(CPLErr, CPLErrorNum, const char* message)
{
    auto* messages = static_cast<Messages*>(CPLGetErrorHandlerUserData());
    if (messages && message) messages->last = message;
}

/// IsValid with GEOS's reason; the reason's point when it names one, else the feature's anchor.
bool check_valid(const LayerData& d, const Feature& f, AssessExample& example)
{
    std::unique_ptr<OGRGeometry> g(d.make_ogr_polygon(f));
    Messages messages;
    CPLPushErrorHandlerEx(remember, &messages);
    const bool valid = g && g->IsValid();
    CPLPopErrorHandler();
    if (valid) return true;
    const Pt p = d.anchor(f);
    example = {f.fid, -1, p.x, p.y, 0, 0, 0, messages.last.empty() ? "invalid" : messages.last, {}};
    const auto at = messages.last.find(" at or near point ");
    double x, y;
    if (at != std::string::npos && std::sscanf(messages.last.c_str() + at + 18, "%lf %lf", &x, &y) == 2)
        example.x = x, example.y = y;
    return false;
}

} // namespace

std::vector<std::uint8_t> measure_validity(const LayerData& a, const LayerData& b, AssessReport& r, std::size_t k)
{
    for (const Feature& f : a.features) r.area_in += a.area(f);
    for (const Feature& f : b.features) {
        r.area_out += b.area(f);
        if (f.kind != FeatureKind::empty) continue;
        ++r.n_empty;
        r.empty.push_back({f.fid, -1, 0, 0, 0, 0, 0, "", {}});
    }
    r.area_change = r.area_in > 0 ? (r.area_out - r.area_in) / r.area_in : 0;
    std::vector<std::uint8_t> invalid(b.features.size(), 0);
    tbb::combinable<std::vector<AssessExample>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, b.features.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
            if (b.features[i].kind != FeatureKind::polygon) continue;
            AssessExample e;
            if (check_valid(b, b.features[i], e)) continue;
            invalid[i] = 1;
            found.local().push_back(std::move(e));
        }
    });
    found.combine_each([&](const auto& v) { r.invalid.insert(r.invalid.end(), v.begin(), v.end()); });
    r.n_invalid = static_cast<std::int64_t>(r.invalid.size());
    keep_first(r.invalid, k, by_fids);
    keep_first(r.empty, k, by_fids);
    return invalid;
}

} // namespace trisnap::assess
