// CommitGroup and the text-file helpers: all staged files or none, never a replaced target
// that must not be replaced, nothing temporary left behind.
#include "config/errors.hpp"
#include "io/commit_group.hpp"
#include "io/io_error.hpp"
#include "io/temp_files.hpp"
#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace trisnap {
namespace {
namespace fs = std::filesystem;

class CommitGroupTest : public ::testing::Test {
protected:
    fs::path path(const std::string& name) const { return m_dir / name; }
    void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }
    std::string read(const std::string& name) const
    {
        std::ifstream in(path(name));
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    std::vector<std::string> names() const
    {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(m_dir)) {
            out.push_back(e.path().filename().string());
        }
        std::sort(out.begin(), out.end());
        return out;
    }

    test::ScratchDir m_scratch;
    const fs::path& m_dir = m_scratch.path();
};

TEST_F(CommitGroupTest, RenamesEveryStagedFileInOrder)
{
    write("a.tmp", "A");
    write("b.tmp", "B");
    CommitGroup group;
    group.stage(path("a.tmp"), path("a"), false, "OUT");
    group.stage(path("b.tmp"), path("b"), false, "--report");
    group.commit();
    EXPECT_TRUE(group.committed());
    EXPECT_EQ(names(), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(read("a") + read("b"), "AB");
}

TEST_F(CommitGroupTest, AnExistingTargetIsNotReplacedAndEarlierRenamesAreUndone)
{
    write("a.tmp", "A");
    write("b.tmp", "B");
    write("b", "keep me");
    CommitGroup group;
    group.stage(path("a.tmp"), path("a"), false, "OUT");
    group.stage(path("b.tmp"), path("b"), false, "OUT");
    EXPECT_THROW(group.commit(), argument_error);
    EXPECT_EQ(read("b"), "keep me");
    EXPECT_FALSE(fs::exists(path("a"))) << "all or nothing";
}

TEST_F(CommitGroupTest, ReplaceAllowedReplaces)
{
    write("a.tmp", "new");
    write("a", "old");
    CommitGroup group;
    group.stage(path("a.tmp"), path("a"), true, "--report");
    group.commit();
    EXPECT_EQ(read("a"), "new");
}

TEST_F(CommitGroupTest, WithoutCommitNothingStagedIsLeft)
{
    fs::create_directory(path("work"));
    write("work/a", "A");
    write("b.tmp", "B");
    {
        CommitGroup group;
        group.stage(path("work/a"), path("a"), false, "OUT");
        group.stage(path("b.tmp"), path("b"), true, "--report");
        group.own_directory(path("work"));
    }
    EXPECT_EQ(names(), std::vector<std::string>{});
}

TEST_F(CommitGroupTest, AProtectedTargetIsRefused)
{
    write("input.gpkg", "precious");
    write("a.tmp", "A");
    ProtectedFiles input;
    input.add_file(path("input.gpkg").string(), "the input");
    CommitGroup group;
    group.stage(path("a.tmp"), path("input.gpkg"), true, "OUT");
    group.protect(input);
    EXPECT_THROW(group.commit(), argument_error);
    EXPECT_EQ(read("input.gpkg"), "precious");
}

TEST_F(CommitGroupTest, TextFileIsWholeOrAbsent)
{
    write_text_file_atomically(path("r.json").string(), "{}\n", {}, "--report");
    EXPECT_EQ(read("r.json"), "{}\n");
    EXPECT_EQ(names(), std::vector<std::string>{"r.json"}) << "no temporary file left";
    EXPECT_THROW(write_text_file_atomically("/dev/full", "x", {}, "--report"), argument_error);
    EXPECT_THROW(write_text_file_atomically(m_dir.string(), "x", {}, "--report"), argument_error);
    EXPECT_THROW(write_text_file_atomically(path("missing/r.json").string(), "x", {}, "--report"), argument_error);
}

TEST_F(CommitGroupTest, StaleTemporariesOfDeadProcessesAreRemoved)
{
    const pid_t dead = fork();
    if (dead == 0) {
        _exit(0);
    }
    waitpid(dead, nullptr, 0);
    fs::create_directory(path(".out.gpkg.trisnap-tmp-" + std::to_string(dead)));
    fs::create_directory(path(".out.gpkg.trisnap-tmp-" + std::to_string(getpid())));
    fs::create_directory(path(".other.gpkg.trisnap-tmp-" + std::to_string(dead)));
    fs::create_directory(path(".out.gpkg.trisnap-tmp-12x"));
    remove_stale_temporaries(path("out.gpkg"));
    std::vector<std::string> expected{".other.gpkg.trisnap-tmp-" + std::to_string(dead),
                                      ".out.gpkg.trisnap-tmp-" + std::to_string(getpid()), ".out.gpkg.trisnap-tmp-12x"};
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(names(), expected);
}

TEST_F(CommitGroupTest, TempDirectoryGoesAwayUnlessReleased)
{
    fs::path kept;
    {
        TempDirectory temp(path("out.gpkg"), "out.gpkg");
        EXPECT_TRUE(fs::is_directory(temp.path()));
        write(temp.path().filename().string() + "/x", "x");
    }
    EXPECT_EQ(names(), std::vector<std::string>{});
    {
        TempDirectory temp(path("out.gpkg"), "out.gpkg");
        kept = temp.release();
    }
    EXPECT_TRUE(fs::is_directory(kept));
}

} // namespace
} // namespace trisnap
