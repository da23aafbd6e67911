#pragma once
// Counted nouns for people: "1 problem", "2 problems", "1 vertex", "3 vertices".
#include <fmt/format.h>

#include <string>

namespace trisnap {

/// "N noun" with `plural_form` (default: noun + "s") unless N is 1.
inline std::string count_of(long long n, const std::string& noun, const std::string& plural_form = "")
{
    const std::string many = plural_form.empty() ? noun + "s" : plural_form;
    return fmt::format("{} {}", n, n == 1 ? noun : many);
}

} // namespace trisnap
