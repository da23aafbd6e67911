// trisnap: snap rounding of GIS polygon and line layers in a constrained Delaunay triangulation.
// main() parses, runs one subcommand and turns each error type into one line and an exit code:
// 0 ok, 1 processing or I/O error, 2 bad arguments or config, 3 problems under --strict.
#include "app/command.hpp"
#include "app/exit_status.hpp"
#include "app/options.hpp"
#include "app/version.hpp"

#include <gdal_priv.h>

#include <iostream>

namespace {

int fail(int code, const std::string& message)
{
    std::cerr << "trisnap: error: " << message << "\n";
    return code;
}

int run_command(trisnap::Command& command)
{
    try {
        return command.run();
    } catch (const std::exception& e) {
        const trisnap::ExitStatus status = trisnap::exit_status(e);
        return fail(status.code, status.message);
    }
}

} // namespace

int main(int argc, char** argv)
{
    GDALAllRegister();
    CLI::App app{"trisnap: snap rounding of polygon and line layers (any OGR format)", "trisnap"};
    app.set_version_flag("--version", trisnap::k_version);
    app.require_subcommand(1);
    std::vector<std::pair<CLI::App*, std::unique_ptr<trisnap::Command>>> commands;
    for (auto make : {trisnap::make_snap_command, trisnap::make_validate_command, trisnap::make_info_command,
                      trisnap::make_problems_command, trisnap::make_assess_command,
                      trisnap::make_render_command}) {
        auto command = make();
        CLI::App* sub = command->setup(app);
        commands.emplace_back(sub, std::move(command));
    }
    std::vector<std::string> args = trisnap::normalise_arguments(argc, argv);
    std::vector<char*> pointers;
    for (std::string& a : args) pointers.push_back(a.data());
    try {
        app.parse(static_cast<int>(pointers.size()), pointers.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        return fail(2, std::string(e.what()) + " (see trisnap --help)");
    }
    for (auto& [sub, command] : commands)
        if (sub->parsed()) return run_command(*command);
    return fail(2, "no command given (see trisnap --help)");
}
