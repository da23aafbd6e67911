// Validity (GDAL's IsValid, i.e. GEOS through OGR), empty outputs, and total areas.
// GEOS states why a geometry is invalid as a notice ("Self-intersection at or near point X Y"),
// which GDAL passes on as a CPL warning: a per-thread handler catches it for the example.
#include "assess/measures.hpp"

#include <ogr_geometry.h>
#include <cpl_error.h>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cmath>
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
    if (messages && message) {
        messages->last = message;
    }
}

/// IsValid with GEOS's reason; the reason's point when it names one, else the feature's anchor.
bool check_valid(const LayerData& d, const Feature& f, AssessExample& example)
{
    std::unique_ptr<OGRGeometry> g(d.make_ogr_polygon(f));
    Messages messages;
    CPLPushErrorHandlerEx(remember, &messages);
    const bool valid = g && g->IsValid();
    CPLPopErrorHandler();
    if (valid) {
        return true;
    }
    const Pt p = d.anchor(f);
    example = example_at(f.fid, -1, p, 0, messages.last.empty() ? "invalid" : messages.last);
    const auto at = messages.last.find(" at or near point ");
    double x, y;
    if (at != std::string::npos && std::sscanf(messages.last.c_str() + at + 18, "%lf %lf", &x, &y) == 2) {
        example.x = x;
        example.y = y;
    }
    return false;
}

} // namespace

std::vector<std::uint8_t> invalid_polygons(const LayerData& d, const std::vector<std::uint32_t>* only, AssessReport* r,
                                           std::size_t k)
{
    std::vector<std::uint8_t> invalid(d.features.size(), 0);
    tbb::combinable<std::vector<AssessExample>> found;
    const std::size_t n = only ? only->size() : d.features.size();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const auto& range) {
        for (std::size_t j = range.begin(); j < range.end(); ++j) {
            const std::size_t i = only ? (*only)[j] : j;
            AssessExample e;
            if (d.features[i].kind != FeatureKind::polygon || check_valid(d, d.features[i], e)) {
                continue;
            }
            invalid[i] = 1;
            found.local().push_back(std::move(e));
        }
    });
    if (r) {
        found.combine_each([&](const auto& v) {
            r->invalid.insert(r->invalid.end(), v.begin(), v.end());
            r->n_invalid += static_cast<std::int64_t>(v.size());
        });
        keep_first(r->invalid, k, by_fids);
    }
    return invalid;
}

namespace {

/// Features kept out of the measures; in the output they count as invalid too.
void count_unmeasurable(const LayerData& d, bool output, AssessReport& r)
{
    for (const Feature& f : d.features) {
        if (f.kind != FeatureKind::unmeasurable) {
            continue;
        }
        ++r.n_unmeasurable;
        const char* which = output ? "snapped" : "original";
        r.unmeasurable.push_back(example_at(output ? -1 : f.fid, output ? f.fid : -1, {}, 0, which));
        if (output) {
            ++r.n_invalid;
            const Pt nowhere{std::nan(""), std::nan("")}; // JSON null: there is no place to give
            r.invalid.push_back(example_at(f.fid, -1, nowhere, 0, "a coordinate is not finite or beyond 1e150"));
        }
    }
}

} // namespace

std::vector<std::uint8_t> measure_validity(const Context& c, AssessReport& r)
{
    for (const Feature& f : c.a.features) {
        r.area_in += c.a.area(f);
    }
    for (const Feature& f : c.b.features) {
        r.area_out += c.b.area(f);
        if (f.kind != FeatureKind::empty) {
            continue;
        }
        ++r.n_empty;
        r.empty.push_back(example_at(f.fid, -1, {}));
    }
    r.area_change = r.area_in > 0 ? (r.area_out - r.area_in) / r.area_in : 0;
    count_unmeasurable(c.a, false, r);
    count_unmeasurable(c.b, true, r);
    keep_first(r.unmeasurable, c.k, by_fids);
    keep_first(r.empty, c.k, by_fids);
    return invalid_polygons(c.b, nullptr, &r, c.k);
}

} // namespace trisnap::assess
