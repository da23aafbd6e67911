#include "app/build_id.hpp"

#include "app/version.hpp"
#include "trisnap_build_id.inc" // generated at every build by build_id.cmake

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

namespace trisnap {
namespace {

// FNV-1a: a stable hash, the same in every build (std::hash is not).
std::uint64_t fnv1a(std::string_view text)
{
    std::uint64_t h = 1469598103934665603ULL;
    for (const char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ULL;
    }
    return h;
}

std::string make_build_id()
{
    const std::string_view git = TRISNAP_GIT_BUILD;
    if (!git.empty()) {
        return fmt::format("{}+{}", k_version, git);
    }
    // Without git, this file's compile time stands for the build: a fresh build (a new
    // container image) gets a new id, copies of one binary share it.
    const std::string info = fmt::format("{} {} {}", __DATE__, __TIME__, __VERSION__);
    return fmt::format("{}+c{:012x}", k_version, fnv1a(info) & 0xffffffffffffULL);
}

} // namespace

const std::string& build_id()
{
    static const std::string id = make_build_id();
    return id;
}

} // namespace trisnap
