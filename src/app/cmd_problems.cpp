// `trisnap problems`: the numbered catalogue of problem codes used in reports.
#include "app/command.hpp"
#include "core/problems.hpp"

#include <fmt/format.h>

#include <iostream>

namespace trisnap {
namespace {

const char* group_of(int code)
{
    switch (code / 100) {
    case 1: return "1xx input repaired or rejected";
    case 2: return "2xx snapping";
    case 3: return "3xx seams between tiles";
    case 9: return "9xx input/output";
    default: return "other";
    }
}

class ProblemsCommand : public Command {
public:
    CLI::App* setup(CLI::App& parent) override
    {
        return parent.add_subcommand("problems", "list the problem codes used in reports");
    }

    int run() override
    {
        int group = -1;
        for (const ProblemInfo& info : problem_catalogue()) {
            const int code = static_cast<int>(info.code);
            if (code / 100 != group) {
                std::cout << (group < 0 ? "" : "\n") << group_of(code) << "\n";
                group = code / 100;
            }
            std::cout << fmt::format("  {}  {:<24} {}\n", code, info.name, info.description);
        }
        return 0;
    }
};

} // namespace

std::unique_ptr<Command> make_problems_command() { return std::make_unique<ProblemsCommand>(); }

} // namespace trisnap
