#pragma once

namespace trisnap {
/// The tool's version, from project(VERSION) in the top-level CMakeLists.txt.
inline constexpr const char* k_version = TRISNAP_VERSION;
} // namespace trisnap
