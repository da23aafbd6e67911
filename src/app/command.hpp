#pragma once
// One subcommand: setup() declares its options on CLI11 and does no I/O (parsing and checks
// only); run() does the work and returns the exit code. Errors are thrown as argument_error,
// config_error or io_error and turned into one line by main().
#include <CLI/CLI.hpp>

#include <memory>
#include <vector>

namespace trisnap {

struct SnapArgs;
struct Plan;
struct RunResult;

class Command {
public:
    virtual ~Command() = default;
    virtual CLI::App* setup(CLI::App& parent) = 0;
    virtual int run() = 0;
};

std::unique_ptr<Command> make_snap_command();
std::unique_ptr<Command> make_validate_command();
std::unique_ptr<Command> make_info_command();
std::unique_ptr<Command> make_problems_command();
std::unique_ptr<Command> make_render_command();
std::unique_ptr<Command> make_assess_command();
std::unique_ptr<Command> make_plan_command();
std::unique_ptr<Command> make_snap_tiles_command();
std::unique_ptr<Command> make_stitch_command();

/// The end of a run that wrote OUT (snap, stitch; the --report was committed with OUT): --problems-layer, the summary
/// (stdout, or stderr when OUT is stdout; none with -q); the exit code (3: problems under --strict).
int deliver_run(const SnapArgs& args, const Plan& plan, const RunResult& result, double total_seconds);

/// A clause main() adds to the error line of a failed command (e.g. that a work directory was
/// kept for --resume), so a failure stays one line.
void set_error_note(const std::string& note);
const std::string& error_note();

/// Log level from -v (repeatable) and -q; logs go to stderr, results to stdout.
void setup_logging(int verbose, int quiet);

/// The cores this process may run on (its CPU affinity), at least 1.
int available_cores();

/// Limits GDAL and oneTBB to `threads` (0 = all cores) while it lives.
class ThreadLimit {
public:
    explicit ThreadLimit(int threads);
    ~ThreadLimit();
    ThreadLimit(const ThreadLimit&) = delete;
    ThreadLimit& operator=(const ThreadLimit&) = delete;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace trisnap
