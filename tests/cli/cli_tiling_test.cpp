// `trisnap snap` tiled from the command line: identical bytes for --threads 1 and N, for tiled
// and --no-tiles, run to run; the report lists the tiles; tiling options are checked.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace trisnap::test {
namespace {

const std::string andorra() { return data_dir() + "/snapoly_andorra/andorra.gpkg"; }

TEST(CliTiling, ThreadsTilesAndNoTilesGiveIdenticalBytes)
{
    if (!exists(andorra())) GTEST_SKIP() << "data set absent: " << andorra();
    TempDir dir;
    const std::vector<std::vector<std::string>> variants{
        {"--no-tiles"}, {"--threads", "1"}, {"--threads", "2"}, {"--tile-size", "0.02", "--threads", "1"},
        {"--tile-size", "0.02", "--threads", "2"}, {"--tile-vertex-budget", "3000", "--threads", "2"}};
    std::string first;
    for (std::size_t k = 0; k < variants.size(); ++k) {
        const std::string out = dir.path("out" + std::to_string(k) + ".gpkg");
        std::vector<std::string> args{"snap", andorra(), out, "--tolerance", "1e-6", "-q", "--report", out + ".json"};
        args.insert(args.end(), variants[k].begin(), variants[k].end());
        const RunOutput r = run_trisnap(dir, args);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        const std::string bytes = file_bytes(out);
        ASSERT_FALSE(bytes.empty());
        if (k == 0) first = bytes;
        else EXPECT_EQ(bytes, first) << "variant " << k << " differs from --no-tiles";
        const auto report = read_json(out + ".json");
        EXPECT_EQ(report["tiling"]["tiled"].get<bool>(), k != 0);
        if (k >= 3) {
            EXPECT_GT(report["tiling"]["tiles"].get<int>(), 1);
            EXPECT_EQ(report["tiling"]["list"].size(), report["tiling"]["tiles"].get<std::size_t>());
            std::size_t owned = 0;
            for (const auto& t : report["tiling"]["list"]) owned += t["owned_edges"].get<std::size_t>();
            EXPECT_GT(owned, 0u);
        }
    }
}

TEST(CliTiling, BadTilingOptionsNameTheOption)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--tile-size", "5", "--no-tiles"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--tile-size or --no-tiles"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--halo", "1"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("tiling.halo"), std::string::npos) << r.err;
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--tile-size", "1e-9"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--tile-size"), std::string::npos) << r.err;
    EXPECT_EQ(r.err_lines().size(), 1u) << r.err;
}

TEST(CliTiling, TilingConfigKeysAreReadAndChecked)
{
    TempDir dir;
    const std::string in = dir.path("in.gpkg");
    write_fixture(in, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    const std::string cfg = dir.path("c.toml");
    {
        std::ofstream f(cfg);
        f << "[tiling]\nsize = 5.0\nhalo = 16.0\n";
    }
    RunOutput r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--config", cfg, "--print-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("size = 5.0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("halo = 16.0"), std::string::npos) << r.out;
    {
        std::ofstream f(cfg);
        f << "[tiling]\nsise = 5.0\n";
    }
    r = run_trisnap(dir, {"snap", in, dir.path("o.gpkg"), "--tolerance", "0.01", "--config", cfg});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("tiling.sise"), std::string::npos) << r.err;
}

} // namespace
} // namespace trisnap::test
