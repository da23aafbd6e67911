// exit_status(): the exit code and line for an escaping exception; out of memory wherever nested;
// a full work disk names the work directory.
#include "app/exit_status.hpp"
#include "config/errors.hpp"
#include "io/io_error.hpp"
#include "tiling/work_store.hpp"

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>

namespace trisnap {
namespace {

/// The exception that `thrower` throws, caught as std::exception and mapped.
template <typename F>
ExitStatus status_of(F thrower)
{
    try {
        thrower();
    } catch (const std::exception& e) {
        return exit_status(e);
    }
    return {};
}

TEST(ExitStatus, TypesGiveTheirCodes)
{
    EXPECT_EQ(status_of([] { throw argument_error("--tolerance: bad"); }).code, 2);
    EXPECT_EQ(status_of([] { throw config_error("c.toml", 3, "snap.x", "unknown key"); }).code, 2);
    const ExitStatus io = status_of([] { throw io_error("out.gpkg", "", "cannot write"); });
    EXPECT_EQ(io.code, 1);
    EXPECT_EQ(io.message, "out.gpkg: cannot write");
    EXPECT_EQ(status_of([] { throw std::runtime_error("engine"); }).code, 1);
}

TEST(ExitStatus, OutOfMemoryGetsTheHintAlsoWhenNested)
{
    const ExitStatus plain = status_of([] { throw std::bad_alloc(); });
    EXPECT_EQ(plain.code, 1);
    EXPECT_EQ(plain.message.rfind("out of memory; give --memory-limit", 0), 0u) << plain.message;
    const ExitStatus nested = status_of([] {
        try {
            try {
                throw std::bad_alloc();
            } catch (...) {
                std::throw_with_nested(std::runtime_error("snapping tile 3 (features 17-18)"));
            }
        } catch (...) {
            std::throw_with_nested(std::runtime_error("snapping failed"));
        }
    });
    EXPECT_EQ(nested.code, 1);
    EXPECT_EQ(nested.message.rfind("out of memory;", 0), 0u) << nested.message;
    EXPECT_NE(nested.message.find("(snapping failed)"), std::string::npos) << nested.message;
}

TEST(ExitStatus, FullWorkDiskNamesTheWorkDirectoryInOneLine)
{
    const ExitStatus s = status_of([] {
        throw tiling::disk_full_error("/data/w/features.bin.tmp-h-7: cannot write: No space left on device", "/data/w");
    });
    EXPECT_EQ(s.code, 1);
    EXPECT_EQ(s.message, "work directory /data/w: no room left for the work files (features.bin.tmp-h-7: cannot write: "
                         "No space left on device); free some space there or give --work-dir on a larger disk");
}

TEST(ExitStatus, NestedMessagesAreKept)
{
    const ExitStatus s = status_of([] {
        try {
            throw io_error("in.gpkg", "roads", "corrupt page");
        } catch (...) {
            std::throw_with_nested(std::runtime_error("reading failed"));
        }
    });
    EXPECT_EQ(s.code, 1);
    EXPECT_EQ(s.message, "reading failed: in.gpkg (layer 'roads'): corrupt page");
}

} // namespace
} // namespace trisnap
