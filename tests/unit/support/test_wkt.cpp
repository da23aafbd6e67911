#include "core/wkt.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace trisnap {
namespace {

std::string round_trip(const std::string& text) {
    return to_wkt(read_wkt(text));
}

std::string error_of(const std::string& text) {
    try {
        read_wkt(text);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

TEST(Wkt, CanonicalTextRoundTrips) {
    for (const char* text : {
             "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (2 2, 2 3, 3 3, 2 2))",
             "MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)), ((5 5, 6 5, 6 6, 5 5)))",
             "LINESTRING (0 0, 1.5 -2.25, 1e+300 5e-324)",
             "MULTILINESTRING ((0 0, 1 1), (2 2, 3 3, 4 4))",
             "POLYGON Z ((0 0 1, 1 0 2, 1 1 3, 0 0 1))",
             "POLYGON EMPTY", "MULTIPOLYGON EMPTY", "LINESTRING EMPTY", "MULTILINESTRING EMPTY",
             "GEOMETRYCOLLECTION EMPTY"})
        EXPECT_EQ(round_trip(text), text);
}

TEST(Wkt, ReadsTypesAndStructure) {
    Geometry g = read_wkt("MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0), (0.2 0.1, 0.8 0.1, 0.8 0.7, 0.2 0.1)),"
                          " ((5 5, 6 5, 6 6, 5 5)))");
    EXPECT_EQ(g.type, Geometry::Type::MultiPolygon);
    ASSERT_EQ(g.polygons.size(), 2u);
    EXPECT_EQ(g.polygons[0].rings.size(), 2u);
    EXPECT_EQ(g.polygons[1].rings[0].size(), 4u);
    EXPECT_FALSE(g.has_z);
    EXPECT_TRUE(std::isnan(g.polygons[0].rings[0][0].z));
    EXPECT_TRUE(read_wkt("POLYGON EMPTY").empty());
    EXPECT_EQ(read_wkt("POLYGON EMPTY").type, Geometry::Type::Polygon);
    EXPECT_EQ(read_wkt("GEOMETRYCOLLECTION EMPTY").type, Geometry::Type::Empty);
}

TEST(Wkt, KeywordsAreCaseInsensitiveAndSpacingIsFree) {
    Geometry g = read_wkt("  polygon z((0 0 1,1 0 2 ,1 1 3,0 0 1))  ");
    EXPECT_TRUE(g.has_z);
    EXPECT_EQ(g.polygons[0].rings[0][2].z, 3.0);
    EXPECT_EQ(to_wkt(g), "POLYGON Z ((0 0 1, 1 0 2, 1 1 3, 0 0 1))");
}

TEST(Wkt, ThreeOrdinatesWithoutKeywordAreZ) {
    Geometry g = read_wkt("LINESTRING (0 0 7, 1 1 8)");
    EXPECT_TRUE(g.has_z);
    EXPECT_EQ(g.lines[0][1].z, 8.0);
}

TEST(Wkt, UnclosedRingIsKeptForTheEngineToReport) {
    Geometry g = read_wkt("POLYGON ((0 0, 1 0, 1 1))");
    EXPECT_EQ(g.polygons[0].rings[0].size(), 3u);
}

TEST(Wkt, DoublesRoundTripBitForBit) {
    const double values[] = {0.1, 1.0 / 3.0, -0.0, 5e-324, 1e-300, 123456789.123456789,
                             std::nextafter(1.0, 2.0), 6378137.000000001, -1.7976931348623157e308};
    Geometry g;
    g.type = Geometry::Type::LineString;
    Path line;
    for (double v : values)
        line.push_back(Coord{v, -v});
    g.lines.push_back(line);
    const Geometry back = read_wkt(to_wkt(g));
    ASSERT_EQ(back.lines[0].size(), line.size());
    for (std::size_t i = 0; i < line.size(); ++i) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(back.lines[0][i].x), std::bit_cast<std::uint64_t>(line[i].x));
        EXPECT_EQ(std::bit_cast<std::uint64_t>(back.lines[0][i].y), std::bit_cast<std::uint64_t>(line[i].y));
    }
}

TEST(Wkt, SeveralPartsInASinglePartTypeAreNotDropped) {
    Geometry g = read_wkt("MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)), ((5 5, 6 5, 6 6, 5 5)))");
    g.type = Geometry::Type::Polygon;
    EXPECT_EQ(to_wkt(g), "MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)), ((5 5, 6 5, 6 6, 5 5)))");
}

TEST(Wkt, FewerDigitsRound) {
    Geometry g = read_wkt("LINESTRING (0.123456789 1234567.891, 1 2)");
    EXPECT_EQ(to_wkt(g, 6), "LINESTRING (0.123457 1.23457e+06, 1 2)");
}

TEST(Wkt, NonFiniteCoordinatesAreReadSoTheEngineCanReject) {
    Geometry g = read_wkt("LINESTRING (nan 0, inf -inf)");
    EXPECT_TRUE(std::isnan(g.lines[0][0].x));
    EXPECT_TRUE(std::isinf(g.lines[0][1].y));
}

TEST(Wkt, ErrorsNameThePosition) {
    EXPECT_EQ(error_of("POLYGON ((0 0, 1 0, 1 1 0 0))"),
              "WKT error at position 24: expected ')', found '0'");
    EXPECT_EQ(error_of("POINT (1 2)"),
              "WKT error at position 0: expected POLYGON, MULTIPOLYGON, LINESTRING or "
              "MULTILINESTRING, found 'P'");
    EXPECT_EQ(error_of("POLYGON ((0 0, 1 0, 1 1, 0 0)) x"),
              "WKT error at position 31: unexpected text after the geometry, found 'x'");
    EXPECT_EQ(error_of("LINESTRING (0 0, 1"), "WKT error at position 18: expected a number, found end of text");
    EXPECT_EQ(error_of("LINESTRING (0 0, a 1)"), "WKT error at position 17: expected a number, found 'a'");
    EXPECT_EQ(error_of("LINESTRING M (0 0 1, 1 1 1)"),
              "WKT error at position 11: measured (M) coordinates are not supported, found 'M'");
    EXPECT_EQ(error_of("GEOMETRYCOLLECTION (LINESTRING (0 0, 1 1))"),
              "WKT error at position 19: only GEOMETRYCOLLECTION EMPTY is supported, found '('");
}

TEST(Wkt, ErrorMessagesAreOneLine) {
    for (const char* bad : {"", "POLYGON", "POLYGON ((", "MULTIPOLYGON ((0 0, 1 1))", "LINESTRING (1e999 0, 1 1)"}) {
        const std::string message = error_of(bad);
        EXPECT_NE(message, "no error") << bad;
        EXPECT_EQ(message.find('\n'), std::string::npos) << bad;
        EXPECT_NE(message.find("position"), std::string::npos) << bad;
    }
}

TEST(WktFeatures, ReadsIdsSkipsCommentsAndBlankLines) {
    std::istringstream in("# golden case\n\n1;POLYGON ((0 0, 1 0, 1 1, 0 0))\r\n"
                          "  -7 ; LINESTRING (0 0, 1 1)\n   \n# end\n");
    const std::vector<Feature> features = read_wkt_features(in);
    ASSERT_EQ(features.size(), 2u);
    EXPECT_EQ(features[0].id, 1);
    EXPECT_TRUE(features[0].geometry.is_polygonal());
    EXPECT_EQ(features[1].id, -7);
    EXPECT_TRUE(features[1].geometry.is_lineal());
}

TEST(WktFeatures, ErrorsNameTheLine) {
    std::istringstream no_id("1;LINESTRING (0 0, 1 1)\n\nx;LINESTRING (0 0, 1 1)\n");
    EXPECT_THROW(
        {
            try {
                read_wkt_features(no_id);
            } catch (const std::invalid_argument& e) {
                EXPECT_STREQ(e.what(), "line 3: bad feature id 'x'");
                throw;
            }
        },
        std::invalid_argument);
    std::istringstream bad_wkt("2;LINESTRING (0 0, 1 1\n");
    try {
        read_wkt_features(bad_wkt);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("line 1: WKT error at position", 0), 0u) << e.what();
    }
    std::istringstream no_semicolon("LINESTRING (0 0, 1 1)\n");
    EXPECT_THROW(read_wkt_features(no_semicolon), std::invalid_argument);
}

} // namespace
} // namespace trisnap
