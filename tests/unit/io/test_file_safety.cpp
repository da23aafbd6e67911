// ProtectedFiles: one file under any of its names; the files a driver writes for a dataset.
#include "config/errors.hpp"
#include "io/file_safety.hpp"
#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace trisnap {
namespace {
namespace fs = std::filesystem;

class FileSafetyTest : public ::testing::Test {
protected:
    FileSafetyTest()
    {
        std::ofstream(m_dir / "in.gpkg") << "data";
        fs::create_directory(m_dir / "sub");
        m_input.add_file((m_dir / "in.gpkg").string(), "the input in.gpkg");
    }
    test::ScratchDir m_scratch;
    const fs::path& m_dir = m_scratch.path();
    ProtectedFiles m_input;
};

TEST_F(FileSafetyTest, OneFileUnderEveryName)
{
    fs::create_hard_link(m_dir / "in.gpkg", m_dir / "hard");
    fs::create_symlink(m_dir / "in.gpkg", m_dir / "soft");
    fs::create_directory_symlink(m_dir, m_dir / "sub" / "up");
    for (const fs::path& name : {m_dir / "in.gpkg", m_dir / "hard", m_dir / "soft", m_dir / "sub" / ".." / "in.gpkg",
                                 m_dir / "sub" / "up" / "in.gpkg"}) {
        EXPECT_EQ(m_input.owner_of(name.string()), "the input in.gpkg") << name;
        EXPECT_THROW(m_input.refuse(name.string(), "--report"), argument_error) << name;
    }
}

TEST_F(FileSafetyTest, OtherFilesAndFilesToBeAreNotTheInput)
{
    std::ofstream(m_dir / "other.gpkg") << "data";
    for (const fs::path& name : {m_dir / "other.gpkg", m_dir / "new.gpkg", m_dir / "sub" / "in.gpkg"}) {
        EXPECT_EQ(m_input.owner_of(name.string()), "") << name;
        EXPECT_NO_THROW(m_input.refuse(name.string(), "OUT")) << name;
    }
}

TEST_F(FileSafetyTest, AFileToBeMatchesThroughASymlinkedDirectory)
{
    ProtectedFiles out;
    out.add_file((m_dir / "out.gpkg").string(), "OUT"); // does not exist yet
    fs::create_directory_symlink(m_dir, m_dir / "sub" / "up");
    EXPECT_EQ(out.owner_of((m_dir / "sub" / "up" / "out.gpkg").string()), "OUT");
}

TEST_F(FileSafetyTest, AWorkDirectoryMustNotHoldTheInput)
{
    EXPECT_THROW(m_input.refuse_tree(m_dir.string(), "--work-dir"), argument_error);
    fs::create_directory_symlink(m_dir, m_dir / "sub" / "up");
    EXPECT_THROW(m_input.refuse_tree((m_dir / "sub" / "up").string(), "--work-dir"), argument_error);
    EXPECT_NO_THROW(m_input.refuse_tree((m_dir / "sub").string(), "--work-dir"));
    EXPECT_NO_THROW(m_input.refuse_tree((m_dir / "new").string(), "--work-dir")) << "one to be created";
}

TEST_F(FileSafetyTest, AShapefileIsSeveralFiles)
{
    GDALAllRegister();
    GDALDriver* shp = GetGDALDriverManager()->GetDriverByName("ESRI Shapefile");
    ASSERT_NE(shp, nullptr);
    const std::vector<std::string> files = dataset_files_for("/d/v.dbf", *shp);
    for (const char* f : {"/d/v.dbf", "/d/v.shp", "/d/v.shx", "/d/v.prj", "/d/v.cpg", "/d/v.SHP"}) {
        EXPECT_NE(std::find(files.begin(), files.end(), f), files.end()) << f;
    }
    GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
    const std::vector<std::string> journals = dataset_files_for("/d/o.gpkg", *gpkg);
    EXPECT_NE(std::find(journals.begin(), journals.end(), "/d/o.gpkg-wal"), journals.end());
}

} // namespace
} // namespace trisnap
