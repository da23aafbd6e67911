// The work directory's records round-trip bit for bit: geometries and tile features, cleaned
// features (features.bin: x, y and z, NaN payloads and negative zeros, several rings, parts and
// lines), read back in order and by rank. (A tile's result files: test_tile_result.cpp.)
#include "generators.hpp"
#include "record_checks.hpp"
#include "snap_harness.hpp"

#include "stitch/spool.hpp"
#include "tiling/records.hpp"
#include "tiling/work_store.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <stdexcept>

namespace trisnap {
namespace {

using namespace test_records;
namespace fs = std::filesystem;

TEST(Records, GeometriesAndTileFeaturesRoundTripBitForBit)
{
    for (bool polygon : {true, false}) {
        tiling::TileFeature f{42, Feature{-7, awkward_geometry(polygon)}, false};
        std::string bytes;
        const tiling::TileFeature back = round_trip(f, tiling::put_tile_feature, tiling::get_tile_feature, &bytes);
        EXPECT_EQ(back.rank, 42u);
        EXPECT_EQ(back.feature.id, -7);
        EXPECT_FALSE(back.intact);
        EXPECT_EQ(same_geometry(f.feature.geometry, back.feature.geometry), polygon ? 15u : 7u);
        // Every truncation is refused, never read past the end.
        for (std::size_t cut = 0; cut < bytes.size(); cut += 7) {
            tiling::ByteReader partial(std::string_view(bytes).substr(0, cut), "test");
            EXPECT_THROW(tiling::get_tile_feature(partial), tiling::record_error) << cut;
        }
    }
}

// A cleaned feature by hand (cleaning would reject the extreme values, and the encoding must
// keep whatever it is given): two polygons, one with a hole, and a line feature of three lines.
detail::CleanFeature awkward_clean_feature(bool polygonal)
{
    detail::CleanFeature f;
    f.index = 3;
    f.id = -9;
    f.polygonal = polygonal;
    if (polygonal) {
        f.rings = {{awkward_path(0), 0, false}, {awkward_path(1), 0, true}, {awkward_path(2), 1, false}};
        f.shells = 2;
        f.holes = 1;
    } else {
        f.lines = {awkward_path(0), awkward_path(3), {{1, 2, 3}, {4, 5, 6}}};
    }
    return f;
}

std::size_t same_clean_feature(const detail::CleanFeature& a, const detail::CleanFeature& b, bool has_z)
{
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.polygonal, b.polygonal);
    EXPECT_EQ(a.rejected, b.rejected);
    EXPECT_EQ(a.shells, b.shells);
    EXPECT_EQ(a.holes, b.holes);
    std::size_t compared = 0;
    EXPECT_EQ(a.rings.size(), b.rings.size());
    for (std::size_t k = 0; k < std::min(a.rings.size(), b.rings.size()); ++k) {
        EXPECT_EQ(a.rings[k].hole, b.rings[k].hole) << "ring " << k;
        EXPECT_EQ(a.rings[k].polygon, b.rings[k].polygon) << "ring " << k;
        compared += same_points(a.rings[k].points, b.rings[k].points, has_z);
    }
    EXPECT_EQ(a.lines.size(), b.lines.size());
    for (std::size_t k = 0; k < std::min(a.lines.size(), b.lines.size()); ++k) {
        compared += same_points(a.lines[k], b.lines[k], has_z);
    }
    return compared;
}

TEST(Records, CleanFeaturesRoundTripWithAndWithoutZ)
{
    for (bool polygonal : {true, false}) {
        const detail::CleanFeature cf = awkward_clean_feature(polygonal);
        for (bool has_z : {true, false}) {
            bool back_z = !has_z;
            const detail::CleanFeature back = round_trip(
                cf, [&](tiling::ByteWriter& w, const detail::CleanFeature& f) { tiling::put_clean_feature(w, f, has_z); },
                [&](tiling::ByteReader& r) { return tiling::get_clean_feature(r, back_z); });
            EXPECT_EQ(back_z, has_z);
            EXPECT_EQ(same_clean_feature(cf, back, has_z), polygonal ? 15u : 12u) << "polygonal " << polygonal;
            // The stitch's outline: everything but each path's points after the first.
            std::string bytes;
            tiling::ByteWriter w(bytes);
            tiling::put_clean_feature(w, cf, has_z);
            tiling::ByteReader r(bytes, "test");
            detail::CleanFeature outline = tiling::get_clean_feature(r, back_z, true);
            EXPECT_TRUE(r.done());
            detail::CleanFeature heads = cf;
            for (detail::CleanRing& ring : heads.rings) {
                ring.points.resize(1);
            }
            for (auto& line : heads.lines) {
                line.resize(1);
            }
            EXPECT_EQ(same_clean_feature(heads, outline, has_z), cf.rings.size() + cf.lines.size()) << "polygonal " << polygonal;
            // The outline's record made from the whole record's bytes (a spool cut to outlines)
            // is the record of the outline, byte for byte.
            std::string cut;
            tiling::ByteWriter cw(cut);
            tiling::ByteReader whole(bytes, "test");
            tiling::put_clean_outline(cw, whole);
            EXPECT_TRUE(whole.done());
            std::string expected;
            tiling::ByteWriter ew(expected);
            tiling::put_clean_feature(ew, heads, has_z);
            EXPECT_EQ(cut, expected) << "polygonal " << polygonal << ", z " << has_z;
        }
    }
}

// The path the run takes: a feature cleaned and spooled (features.bin), then read back in order
// and by rank; several parts, a hole, Z with a NaN payload and negative zeros.
TEST(Records, SpooledFeaturesReadBackAsCleaned)
{
    const double t = 1e-3;
    Geometry g;
    g.type = Geometry::Type::MultiPolygon;
    g.has_z = true;
    g.polygons = {Polygon{{{{0, 0, -0.0}, {10, 0, k_payload_nan}, {10, 10, 1}, {0, 10, 2}, {0, 0, -0.0}},
                           {{2, 2, 3}, {2, 4, 4}, {4, 4, 5e-324}, {4, 2, 6}, {2, 2, 3}}}},
                  Polygon{{{{-0.0, 20, 7}, {5.5, 20, 8}, {5.5, 25.25, 9}, {-0.0, 20, 7}}}}};
    Geometry lines;
    lines.type = Geometry::Type::MultiLineString;
    lines.has_z = false;
    lines.lines = {{{0.1, 0.2}, {0.3, -0.0}}, {{std::nextafter(1.0, 2.0), 1}, {2, 2}, {3, 1}}};
    const std::vector<Feature> input{{5, g}, {6, lines}};
    auto store = tiling::make_memory_store();
    std::vector<detail::CleanFeature> cleaned;
    {
        stitch::FeatureSpool spool(*store, t, 1000, 64);
        for (std::size_t i = 0; i < input.size(); ++i) {
            std::vector<Problem> problems;
            cleaned.push_back(detail::clean_feature(input[i].id, input[i].geometry, i, t, problems));
            ASSERT_FALSE(cleaned.back().rejected) << problem_lines(problems);
            spool.add(i, input[i].id, input[i].geometry, problems);
        }
        spool.finish();
    }
    ASSERT_EQ(cleaned[0].rings.size(), 3u);
    ASSERT_EQ(cleaned[1].lines.size(), 2u);
    stitch::SpooledFeatures in_order(*store);
    stitch::FeatureLookup by_rank(*store);
    detail::CleanFeature back;
    bool has_z = false;
    std::size_t compared = 0;
    for (std::size_t i = 0; i < input.size(); ++i) {
        ASSERT_TRUE(in_order.next(back, has_z));
        EXPECT_EQ(has_z, input[i].geometry.has_z);
        compared += same_clean_feature(cleaned[i], back, has_z);
    }
    EXPECT_FALSE(in_order.next(back, has_z));
    for (std::size_t i = input.size(); i-- > 0;) { // by rank, backwards
        const detail::CleanFeature at = by_rank.at(i, has_z);
        EXPECT_EQ(has_z, input[i].geometry.has_z);
        compared += same_clean_feature(cleaned[i], at, has_z);
    }
    EXPECT_EQ(compared, 2u * (4 + 4 + 3 + 2 + 3));
}

// The read phase's second reader spools its part of the layer (stitch::SpoolPart), in memory or
// spilled to files of the store (out of core), and the first appends it: every work file and the
// meta must be those of the sequential spool, whatever the cut, with features the cleaning
// repairs or rejects and features skipped on either side, and with the FID check's runs spilled
// (a buffer of 64 FIDs); a spilled part's files are gone after the append.
TEST(SpoolPart, AppendedPartGivesTheSequentialSpool)
{
    const double t = 1e-3;
    std::vector<Feature> input = perturbed_grid_coverage(12, 12, 1.0, 0.2, 3, 1, 0.004);
    Feature repeated; // repaired by the cleaning (problem 104), spooled
    repeated.id = 5000;
    repeated.geometry.type = Geometry::Type::Polygon;
    repeated.geometry.polygons = {Polygon{{{{0, 0}, {4, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 0}}}}};
    input.insert(input.begin() + 40, repeated);
    Feature bad; // rejected by the cleaning (a NaN)
    bad.id = 5001;
    bad.geometry.type = Geometry::Type::Polygon;
    bad.geometry.polygons = {Polygon{{{{0, 0}, {std::nan(""), 0}, {1, 1}, {0, 0}}}}};
    input.insert(input.begin() + 100, bad);
    const auto skipped = [](std::size_t i) { return i % 17 == 5; }; // passed through: FID only
    const auto files = [](tiling::WorkStore& store) {
        std::vector<std::string> out;
        for (const std::string& name : {stitch::files::features, stitch::files::offsets, stitch::files::spool_meta}) {
            out.push_back(store.get(name));
        }
        return out;
    };
    const fs::path dir = fs::temp_directory_path() / ("trisnap-part-" + std::to_string(::getpid()));
    const auto make_store = [&](bool on_disk) {
        fs::remove_all(dir);
        return on_disk ? tiling::make_directory_store(dir.string()) : tiling::make_memory_store();
    };
    std::vector<std::vector<Problem>> expected_problems(input.size());
    tiling::PlanInput expected_sample;
    std::vector<std::string> expected_files[2]; // in memory, on disk (its meta keeps the sample)
    for (const bool on_disk : {false, true}) {
        auto whole = make_store(on_disk);
        stitch::FeatureSpool spool(*whole, t, 200, 64);
        for (std::size_t i = 0; i < input.size(); ++i) {
            if (skipped(i)) {
                spool.skip(input[i].id);
            } else {
                expected_problems[i].clear();
                spool.add(i, input[i].id, input[i].geometry, expected_problems[i]);
            }
        }
        stitch::SpoolMeta meta = spool.finish();
        EXPECT_TRUE(meta.fids_unique);
        EXPECT_GT(meta.sample.level, 0); // the cap of 200 vertices was passed
        expected_sample = std::move(meta.sample);
        expected_files[on_disk ? 1 : 0] = files(*whole);
    }
    EXPECT_FALSE(expected_problems[40].empty());
    EXPECT_FALSE(expected_problems[100].empty());
    // The part is [cut, end): the features after `end` are added after the append, past the
    // part's bytes. Blocks of 4 MiB hold the part in one; of 64 bytes, one record each; block 0
    // here: the part spilled to the store.
    std::size_t blocks_seen = 0;
    std::size_t spilled_seen = 0;
    for (const bool on_disk : {false, true}) {
        for (const std::size_t block : {std::size_t{4} << 20, std::size_t{64}, std::size_t{0}}) {
            for (const std::size_t cut : {std::size_t{0}, std::size_t{41}, std::size_t{100}, input.size() / 2, input.size()}) {
                const std::size_t end = cut == 41 ? 90 : input.size();
                SCOPED_TRACE("cut at " + std::to_string(cut) + ", to " + std::to_string(end) +
                             (block == 0 ? std::string(", spilled") : ", blocks of " + std::to_string(block)) +
                             (on_disk ? ", on disk" : ", in memory"));
                auto store = make_store(on_disk);
                const std::vector<std::string>& expected = expected_files[on_disk ? 1 : 0];
                stitch::FeatureSpool spool(*store, t, 200, 64);
                stitch::SpoolPart part = block == 0 ? stitch::SpoolPart(t, 200, *store, "part-") : stitch::SpoolPart(t, 200, block);
                std::vector<std::vector<Problem>> problems(input.size());
                const auto take = [&](std::size_t i, auto& into) {
                    if (skipped(i)) {
                        into.skip(input[i].id);
                    } else {
                        into.add(i, input[i].id, input[i].geometry, problems[i]);
                    }
                };
                for (std::size_t i = 0; i < end; ++i) {
                    i < cut ? take(i, spool) : take(i, part);
                }
                blocks_seen = std::max(blocks_seen, part.blocks());
                if (part.spilled()) {
                    EXPECT_EQ(part.blocks(), 0u); // nothing held
                    EXPECT_THROW(spool.append(std::move(part)), std::logic_error) << "appended before it was sealed";
                    part.seal();
                    EXPECT_TRUE(store->exists("part-features") && store->exists("part-fids"));
                    ++spilled_seen;
                }
                spool.append(std::move(part));
                EXPECT_FALSE(store->exists("part-features") || store->exists("part-fids")) << "the part's files stayed";
                for (std::size_t i = end; i < input.size(); ++i) {
                    take(i, spool);
                }
                const stitch::SpoolMeta meta = spool.finish();
                EXPECT_TRUE(meta.fids_unique);
                const std::vector<std::string> got = files(*store); // compared without printing megabytes
                for (std::size_t k = 0; k < got.size(); ++k) {
                    EXPECT_TRUE(got[k] == expected[k]) << "file " << k << ": " << got[k].size() << " bytes, expected " << expected[k].size();
                }
                EXPECT_EQ(meta.sample.level, expected_sample.level);
                EXPECT_EQ(meta.sample.xs, expected_sample.xs);
                EXPECT_EQ(meta.sample.ys, expected_sample.ys);
                for (std::size_t i = 0; i < input.size(); ++i) {
                    EXPECT_EQ(problem_lines(problems[i]), problem_lines(expected_problems[i])) << "feature " << i;
                }
            }
        }
    }
    fs::remove_all(dir);
    EXPECT_GT(blocks_seen, 50u); // the small blocks did split the part
    EXPECT_EQ(spilled_seen, 10u);
    // A FID repeated across the cut is found as if read in one go, the part in memory or spilled.
    for (const bool spilled : {false, true}) {
        auto store = tiling::make_memory_store();
        stitch::FeatureSpool spool(*store, t, 200, 64);
        stitch::SpoolPart part = spilled ? stitch::SpoolPart(t, 200, *store, "part-") : stitch::SpoolPart(t, 200);
        for (std::size_t i = 0; i < 70; ++i) {
            spool.skip(static_cast<std::int64_t>(i));
        }
        part.skip(3);
        part.seal();
        spool.append(std::move(part));
        EXPECT_FALSE(spool.finish().fids_unique) << (spilled ? "spilled" : "in memory");
    }
}


// BufferedReader: a file read back in pieces of any size (one byte, a record's 16, more than the
// buffer at once) through buffers smaller and larger than the pieces gives its bytes in order,
// fewer only at the end; in memory and on disk alike.
TEST(BufferedReader, PiecesOfAnySizeGiveTheFileInOrder)
{
    std::string bytes(100003, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        bytes[i] = static_cast<char>((i * 131 + i / 7) & 0xff);
    }
    const fs::path dir = fs::temp_directory_path() / ("trisnap-buffered-" + std::to_string(::getpid()));
    for (const bool on_disk : {false, true}) {
        fs::remove_all(dir);
        const auto store = on_disk ? tiling::make_directory_store(dir.string()) : tiling::make_memory_store();
        store->put("f.bin", bytes);
        for (const std::size_t buffer : {std::size_t{1}, std::size_t{10}, std::size_t{4096}, std::size_t{1} << 20}) {
            for (const std::size_t piece : {std::size_t{1}, std::size_t{16}, std::size_t{5000}}) {
                const auto file = store->open("f.bin");
                tiling::BufferedReader in(*file, buffer);
                std::string got;
                std::string chunk(piece, '\0');
                for (;;) {
                    const std::size_t k = in.read(chunk.data(), piece);
                    got.append(chunk, 0, k);
                    if (k < piece) {
                        break;
                    }
                }
                EXPECT_TRUE(got == bytes) << "on disk " << on_disk << ", buffer " << buffer << ", pieces of " << piece
                                          << ": " << got.size() << " bytes";
                EXPECT_EQ(in.read(chunk.data(), piece), 0u) << "stays at its end";
            }
        }
    }
    fs::remove_all(dir);
}

} // namespace
} // namespace trisnap
