#pragma once
// How main() turns an exception escaping a command into one line on stderr and an exit code:
// 2 for argument_error and config_error (the user can fix the command), 1 for everything else
// (io_error, engine failures). Out of memory gets an actionable hint wherever it happened: a
// std::bad_alloc thrown as is, or nested inside another exception (std::throw_with_nested) by
// a layer that added context such as the tile and the features being snapped.
#include <exception>
#include <string>

namespace trisnap {

struct ExitStatus {
    int code = 1;
    std::string message; ///< without the "trisnap: error: " prefix
};

/// True when `e` is a std::bad_alloc or has one nested inside it, at any depth.
bool is_out_of_memory(const std::exception& e);

ExitStatus exit_status(const std::exception& e);

} // namespace trisnap
