// The render side of sites (measured and ranked by assess, tested in tests/assess): how much
// room a panel gives a site, where it is centred, and the identity colours of coverage panels.
#include "render/scene.hpp"
#include "render/sites.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>

namespace trisnap::render {
namespace {

Site site(SiteKind kind, double value)
{
    Site s;
    s.kind = kind;
    s.at = {10, 0};
    s.other = {10 + value, 0};
    s.value = value;
    return s;
}

TEST(RenderSites, PanelsLeaveRoomForTheSite)
{
    EXPECT_DOUBLE_EQ(panel_half_size(site(SiteKind::drift, 3), 1.0), 7.5) << "2.5 times a far drift";
    EXPECT_DOUBLE_EQ(panel_half_size(site(SiteKind::drift, 1), 1.0), 6.0) << "at least 6 T";
    EXPECT_DOUBLE_EQ(panel_half_size(site(SiteKind::vertex_vertex, 0.4), 1.0), 6.0);
    Site lost = site(SiteKind::missing, 0.15);
    lost.extent = assess::Box{40, 0, 40.4, 0.3};
    EXPECT_DOUBLE_EQ(panel_half_size(lost, 1.0), 0.4 * 0.75 + 4) << "the lost feature and 4 T around it";
    EXPECT_EQ(site_centre(lost), (XY{40.2, 0.15})) << "centred on the lost feature";
    EXPECT_EQ(site_centre(site(SiteKind::vertex_edge, 0.2)), (XY{10.1, 0})) << "midway between the pair";
}

TEST(RenderIdentity, AFeatureAndItsSnappedSelfShareAColourNeighboursDoNot)
{
    EXPECT_EQ(identity_of("42"), identity_of(std::string("4") + "2"));
    const Rgba a = identity_colour(identity_of("42"));
    const Rgba b = identity_colour(identity_of("42"));
    EXPECT_EQ(std::tie(a.r, a.g, a.b, a.a), std::tie(b.r, b.g, b.b, b.a));
    EXPECT_LT(a.a, 255) << "translucent: the thin input stays visible under it";
    std::set<std::tuple<int, int, int>> colours;
    int darkest = 255;
    for (int fid = 1; fid <= 1000; ++fid) {
        const Rgba c = identity_colour(identity_of(std::to_string(fid)));
        colours.insert({c.r, c.g, c.b});
        darkest = std::min({darkest, static_cast<int>(c.r), static_cast<int>(c.g), static_cast<int>(c.b)});
    }
    EXPECT_GE(darkest, 140) << "light enough for outlines on top";
    EXPECT_GT(colours.size(), 500u) << "consecutive FIDs spread over hues and lightnesses";
}

} // namespace
} // namespace trisnap::render
