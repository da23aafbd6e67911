// FieldFidelity: what a dBASE file keeps of a value, and type conversions that lose something.
#include "io/field_fidelity.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace trisnap {
namespace {

/// One field each way: input `from`, output `to` with the given width and decimals.
class OneField {
public:
    OneField(OGRFieldType from, OGRFieldType to, int width, int decimals, const std::string& driver,
             const std::string& out_name = "f")
    {
        OGRFieldDefn in_field("f", from);
        OGRFieldDefn out_field(out_name.c_str(), to);
        out_field.SetWidth(width);
        out_field.SetPrecision(decimals);
        m_in->Reference(); // ours: features built on it must not delete it when they go
        m_out->Reference();
        m_in->AddFieldDefn(&in_field);
        m_out->AddFieldDefn(&out_field);
        m_fidelity = std::make_unique<FieldFidelity>(*m_in, *m_out, std::vector<int>{0}, driver);
    }
    ~OneField()
    {
        m_in->Release();
        m_out->Release();
    }

    /// The problems for `value` (as text) written through the output field.
    std::vector<Problem> write(const std::string& value)
    {
        OGRFeature source(m_in);
        source.SetField(0, value.c_str());
        OGRFeature written(m_out);
        int map = 0;
        written.SetFieldsFrom(&source, &map, TRUE);
        std::vector<Problem> problems;
        m_fidelity->check(source, written, 7, problems);
        return problems;
    }
    FieldFidelity& fidelity() { return *m_fidelity; }

private:
    OGRFeatureDefn* m_in = new OGRFeatureDefn("in");
    OGRFeatureDefn* m_out = new OGRFeatureDefn("out");
    std::unique_ptr<FieldFidelity> m_fidelity;
};

TEST(FieldFidelity, DbfRealsAreRoundedToTheirDecimalsAndCutToTheirWidth)
{
    OneField f(OFTReal, OFTReal, 24, 15, "ESRI Shapefile");
    EXPECT_TRUE(f.write("0.25").empty());
    EXPECT_TRUE(f.write("0.3333333333333333").empty()) << "a change below 1e-12 relative is kept";
    EXPECT_TRUE(f.write("1e20").empty()) << "cut after the integer digits: the value survives";
    const auto tiny = f.write("1e-300");
    ASSERT_EQ(tiny.size(), 1u);
    EXPECT_EQ(tiny[0].code, ProblemCode::value_changed);
    EXPECT_EQ(tiny[0].feature_id, 7);
    EXPECT_NE(tiny[0].message.find("stored as 0"), std::string::npos) << tiny[0].message;
    const auto small = f.write("1.234567e-10");
    ASSERT_EQ(small.size(), 1u) << "digits lost below the 15th decimal";
    const auto huge = f.write("-1e300");
    ASSERT_EQ(huge.size(), 1u);
    EXPECT_NE(huge[0].message.find("too wide"), std::string::npos) << huge[0].message;
}

TEST(FieldFidelity, DbfStringsAreCutAt254Bytes)
{
    OneField f(OFTString, OFTString, 80, 0, "ESRI Shapefile");
    EXPECT_TRUE(f.write(std::string(254, 'x')).empty());
    const auto cut = f.write(std::string(255, 'x'));
    ASSERT_EQ(cut.size(), 1u);
    EXPECT_NE(cut[0].message.find("cut to 254 bytes (255 bytes)"), std::string::npos) << cut[0].message;
    std::string accents;
    for (int i = 0; i < 128; ++i) {
        accents += "\xC3\xA9"; // 128 characters, 256 bytes
    }
    EXPECT_EQ(f.write(accents).size(), 1u) << "the limit is in bytes";
}

TEST(FieldFidelity, OtherDriversKeepWhatTheirFieldTypeHolds)
{
    OneField f(OFTReal, OFTReal, 24, 15, "GPKG");
    EXPECT_TRUE(f.write("1e-300").empty()) << "width and decimals bind only a .dbf";
    OneField text(OFTString, OFTString, 10, 0, "GPKG");
    EXPECT_TRUE(text.write(std::string(300, 'x')).empty());
}

TEST(FieldFidelity, ConversionsThatLoseSomethingAreChanges)
{
    OneField date(OFTDateTime, OFTDate, 0, 0, "GeoJSON");
    EXPECT_TRUE(date.write("2020-01-02T00:00:00").empty());
    EXPECT_EQ(date.write("2020-01-02T03:04:05").size(), 1u);
    OneField integer(OFTReal, OFTInteger, 0, 0, "GeoJSON");
    EXPECT_TRUE(integer.write("3").empty());
    EXPECT_EQ(integer.write("3.5").size(), 1u);
    OneField text(OFTInteger64, OFTString, 0, 0, "GeoJSON");
    EXPECT_TRUE(text.write("12345678901234").empty());
}

TEST(FieldFidelity, RenamedFieldsAndOneSummaryLinePerKind)
{
    OneField f(OFTString, OFTString, 80, 0, "ESRI Shapefile", "g");
    ASSERT_EQ(f.fidelity().renamed_fields().size(), 1u);
    EXPECT_EQ(f.fidelity().renamed_fields()[0].feature_id, -1);
    EXPECT_EQ(f.fidelity().renamed_fields()[0].code, ProblemCode::field_renamed);
    f.write(std::string(300, 'x'));
    f.write(std::string(400, 'y'));
    const auto lines = f.fidelity().summary();
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0], "field 'f': 2 values cut to 254 bytes (first FID 7; problem 903)");
    EXPECT_EQ(lines[1], "field 'f' is named 'g' in the output (problem 904)");
}

} // namespace
} // namespace trisnap
