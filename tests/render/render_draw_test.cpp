// Drawing helpers of `trisnap render`: clipping, dropping sub-pixel steps, the view transform
// and the glyph table.
#include "render/clip.hpp"
#include "render/font.hpp"
#include "render/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace trisnap::render {
namespace {

double ring_area(const std::vector<XY>& ring)
{
    double twice = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const XY a = ring[i], b = ring[(i + 1) % ring.size()];
        twice += a.x * b.y - b.x * a.y;
    }
    return std::abs(twice) / 2;
}

TEST(RenderClip, RingKeepsOnlyThePartInsideTheBox)
{
    const std::vector<XY> ring{{-5, -5}, {5, -5}, {5, 5}, {-5, 5}, {-5, -5}};
    const auto clipped = clip_ring(ring, Box{0, 0, 10, 10});
    EXPECT_DOUBLE_EQ(ring_area(clipped), 25.0);
    for (XY p : clipped) EXPECT_TRUE((Box{0, 0, 10, 10}).contains(p));
    EXPECT_TRUE(clip_ring(ring, Box{20, 20, 30, 30}).empty());
    const auto around = clip_ring({{-50, -50}, {50, -50}, {50, 50}, {-50, 50}}, Box{0, 0, 10, 10});
    EXPECT_DOUBLE_EQ(ring_area(around), 100.0) << "a ring around the box becomes the box";
}

TEST(RenderClip, LineIsCutIntoThePiecesInside)
{
    // In, out, and back in: two pieces.
    const auto pieces = clip_line({{1, 1}, {5, 1}, {5, 20}, {8, 20}, {8, 5}}, Box{0, 0, 10, 10});
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_EQ(pieces[0], (std::vector<XY>{{1, 1}, {5, 1}, {5, 10}}));
    EXPECT_EQ(pieces[1], (std::vector<XY>{{8, 10}, {8, 5}}));
    EXPECT_TRUE(clip_line({{20, 20}, {30, 30}}, Box{0, 0, 10, 10}).empty());
}

TEST(RenderClip, CloseStepsAreDroppedEndsKept)
{
    const auto kept = drop_close_points({{0, 0}, {0.1, 0}, {1, 0}, {1.1, 0}, {1.2, 0}}, 0.35);
    EXPECT_EQ(kept, (std::vector<XY>{{0, 0}, {1.2, 0}})) << "the last point replaces the last kept when close to it";
    EXPECT_EQ(drop_close_points({{0, 0}, {0.1, 0}}, 0.35).size(), 2u) << "a tiny feature stays a dot";
}

TEST(RenderView, FitsCentresAndFlipsY)
{
    const View view(Box{0, 0, 100, 50}, Box{10, 10, 210, 210}, 1.0);
    EXPECT_DOUBLE_EQ(view.px_per_unit_x(), 2.0);
    const XY centre = view.to_px({50, 25});
    EXPECT_DOUBLE_EQ(centre.x, 110);
    EXPECT_DOUBLE_EQ(centre.y, 110);
    EXPECT_LT(view.to_px({50, 40}).y, centre.y) << "north is up";
    EXPECT_DOUBLE_EQ(view.world().height(), 100) << "the shown box fills the panel";
}

TEST(RenderView, GeographicLayersAreDrawnWithTheirProportions)
{
    const CrsInfo geographic{CrsInfo::Kind::geographic, 0, "deg"};
    EXPECT_NEAR(x_stretch_for(geographic, Box{1, 59, 3, 61}), 0.5, 1e-12);
    EXPECT_EQ(x_stretch_for(geographic, Box{-180, -90, 180, 90}), 1.0) << "the whole world stays plate carree";
    EXPECT_EQ(x_stretch_for(CrsInfo{}, Box{1, 59, 3, 61}), 1.0);
    EXPECT_EQ(x_stretch_for(geographic, Box{240, 95, 250, 100}), 1.0) << "y beyond 90 is no latitude";
    EXPECT_EQ(metres(geographic, 1.0, 120), 0.0);
    EXPECT_NEAR(metres(geographic, 1e-5, 0), 1.11319, 1e-4);
    EXPECT_DOUBLE_EQ(metres(CrsInfo{CrsInfo::Kind::projected, 0.3048, "ft"}, 10, 0), 3.048);
}

TEST(RenderFont, EveryPrintableCharacterHasItsOwnGlyph)
{
    int blank = 0;
    for (char c = 33; c < 127; ++c) {
        bool ink = false;
        for (auto row : glyph(c)) ink = ink || row != 0;
        blank += !ink;
        for (char d = static_cast<char>(c + 1); d < 127; ++d)
            EXPECT_NE(glyph(c), glyph(d)) << "'" << c << "' and '" << d << "' look the same";
    }
    EXPECT_EQ(blank, 0);
    EXPECT_EQ(glyph('\x01'), glyph('?'));
}

} // namespace
} // namespace trisnap::render
