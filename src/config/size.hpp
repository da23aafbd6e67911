#pragma once
// Sizes written by people: `--memory-limit 2GiB`, `memory_limit = "512MiB"`.
#include <cstdint>
#include <string>

namespace trisnap {

/// "2GiB", "512MiB", "1.5G", "800MB", "1073741824": binary units for KiB/MiB/GiB/TiB and for a
/// bare K/M/G/T, decimal for KB/MB/GB/TB, bytes without a unit. Throws argument_error naming
/// `what` (the option or key) for anything else, for 0 and for values that do not fit.
std::uint64_t parse_size(const std::string& text, const std::string& what);

/// "1.50 GiB", "512 MiB", "900 KiB".
std::string format_size(std::uint64_t bytes);

} // namespace trisnap
