// trisnap: snap rounding of GIS polygon and line layers in a constrained Delaunay triangulation.
// main() parses, runs one subcommand and turns each error type into one line and an exit code:
// 0 ok, 1 processing or I/O error, 2 bad arguments or config, 3 problems under --strict.
#include "app/about.hpp"
#include "app/allocator.hpp"
#include "app/arguments.hpp"
#include "app/command.hpp"
#include "app/suggest.hpp"
#include "config/errors.hpp"
#include "io/gpkg_rows.hpp"
#include "io/io_error.hpp"
#include "app/exit_status.hpp"
#include "app/options.hpp"
#include "app/version.hpp"

#include <gdal_priv.h>

#include <iostream>
#include <string>

namespace {

int fail(int code, const std::string& message)
{
    const std::string& note = trisnap::error_note();
    std::cerr << "trisnap: error: " << message << (note.empty() ? "" : "; " + note) << "\n";
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

constexpr const char* k_gdal_config = "--config KEY VALUE sets a GDAL configuration option, as in GDAL's tools "
                                      "(anywhere on the line)";
constexpr const char* k_exit = "Exit status: 0 done, 1 processing or I/O error, 2 bad arguments or settings";

const std::string k_footer =
    std::string(k_gdal_config) + "; --config FILE.toml is --settings FILE.toml.\n"
    "ogr2ogr spellings work too: -nln, -lco, -dsco, -oo, -where, -spat xmin ymin xmax ymax, -select, "
    "-overwrite, -progress, -skipfailures.\n"
    "Exit status: 0 done (problems may have been reported), 1 processing or I/O error, "
    "2 bad arguments or settings, 3 problems were reported and --strict was given.";

/// Each command's --help footer names only what it takes (CLI11 copies the root's footer into
/// every subcommand: assess listed -nln and --strict, which it does not have).
std::string footer_of(const std::string& command)
{
    if (command == "snap" || command == "validate") {
        return k_footer;
    }
    if (command == "plan") {
        return std::string(k_gdal_config) + "; --config FILE.toml is --settings FILE.toml.\n"
               "ogr2ogr spellings work too: -oo, -where, -spat xmin ymin xmax ymax.\n" + k_exit + ".";
    }
    if (command == "stitch") {
        return std::string(k_gdal_config) + ".\n" + k_exit + ", 3 problems were reported and --strict was given.";
    }
    if (command == "assess") {
        return std::string(k_gdal_config) + ".\n" + k_exit + ", 3 the contract does not hold and --fail-on-defects "
               "was given.";
    }
    return std::string(k_gdal_config) + ".\n" + k_exit + ".";
}

} // namespace

int main(int argc, char** argv)
{
    trisnap::keep_freed_memory();
    trisnap::sqlite_without_memory_statistics(); // before GDAL opens anything (io/gpkg_rows.hpp)
    trisnap::Arguments arguments;
    try {
        arguments = trisnap::normalise_arguments(argc, argv);
    } catch (const trisnap::argument_error& e) {
        return fail(2, e.what());
    }
    trisnap::apply_gdal_config(arguments);
    GDALAllRegister();
    CLI::App app{"trisnap: snap rounding of polygon and line layers (any OGR format)", "trisnap"};
    app.footer(k_footer);
    trisnap::add_global_flags(app);
    app.require_subcommand(1);
    std::vector<std::pair<CLI::App*, std::unique_ptr<trisnap::Command>>> commands;
    for (auto make : {trisnap::make_snap_command, trisnap::make_validate_command, trisnap::make_info_command,
                      trisnap::make_problems_command, trisnap::make_assess_command,
                      trisnap::make_render_command, trisnap::make_plan_command, trisnap::make_snap_tiles_command,
                      trisnap::make_stitch_command}) {
        auto command = make();
        CLI::App* sub = command->setup(app);
        sub->footer(footer_of(sub->get_name()));
        commands.emplace_back(sub, std::move(command));
    }
    std::vector<char*> pointers;
    for (std::string& a : arguments.argv) {
        pointers.push_back(a.data());
    }
    try {
        app.parse(static_cast<int>(pointers.size()), pointers.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {
            return app.exit(e);
        }
        return fail(2, trisnap::explain_parse_error(app, arguments.argv, e));
    }
    for (auto& [sub, command] : commands) {
        if (sub->parsed()) {
            return run_command(*command);
        }
    }
    return fail(2, "no command given (see trisnap --help)");
}
