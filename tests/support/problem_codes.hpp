#pragma once
// The problem codes the tests judge by, as plain numbers (the contract checker and the CLI
// tests know no engine type on purpose). One list, shared by the engine tests (snap_harness),
// the fuzzer, the CLI tests and the contract checks of real layers, so that what may excuse a
// missing feature is decided in one place.
#include <algorithm>
#include <vector>

namespace trisnap {

/// Codes that mean "this feature is not in the output" (README "What you get"): rejected on
/// input or by the engine (106 non-finite coordinate, 107 empty, 108 unsupported type, 109
/// huge coordinate, 110 unreadable geometry), collapsed entirely (201 polygon, 202 line), its
/// tile failed (303, --on-error skip), not read or refused by the driver (901, 902). No other
/// code may excuse a missing feature: 102 (repeated points removed) says the feature stays.
inline const std::vector<int>& not_written_codes()
{
    static const std::vector<int> codes{106, 107, 108, 109, 110, 201, 202, 303, 901, 902};
    return codes;
}

inline bool is_not_written_code(int code)
{
    const std::vector<int>& codes = not_written_codes();
    return std::find(codes.begin(), codes.end(), code) != codes.end();
}

/// Codes that report a lost shared boundary: 210 (shared_boundary_lost, on both features of the
/// pair). They excuse nothing else (not drift, not an overlap).
inline const std::vector<int>& lost_boundary_codes()
{
    static const std::vector<int> codes{210};
    return codes;
}

} // namespace trisnap
