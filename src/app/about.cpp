#include "app/about.hpp"

#include "app/build_id.hpp"
#include "app/version.hpp"
#include "io/format_limits.hpp"
#include "io/output_driver.hpp"

#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <tbb/version.h>

#include <iostream>
#include <sstream>

namespace trisnap {
namespace {

std::string geos_version()
{
    int major = 0;
    int minor = 0;
    int patch = 0;
    if (!OGRGetGEOSVersion(&major, &minor, &patch)) {
        return "not built in";
    }
    return fmt::format("{}.{}.{}", major, minor, patch);
}

std::string proj_version()
{
    int major = 0;
    int minor = 0;
    int patch = 0;
    OSRGetPROJVersion(&major, &minor, &patch);
    return fmt::format("{}.{}.{}", major, minor, patch);
}

std::string driver_line(GDALDriver& driver)
{
    const bool reads = driver.GetMetadataItem(GDAL_DCAP_OPEN) != nullptr;
    // Refused formats (io/format_limits.hpp) are not advertised as OUT; conditional ones say when.
    const bool writes = can_write_vector(driver) && format_refusal(driver).empty();
    const std::string condition = writes ? format_condition(driver) : "";
    const char* name = driver.GetMetadataItem(GDAL_DMD_LONGNAME);
    const char* extensions = driver.GetMetadataItem(GDAL_DMD_EXTENSIONS);
    std::string ext;
    std::istringstream words(extensions ? extensions : "");
    for (std::string word; words >> word;) {
        ext += (ext.empty() ? " (." : " .") + word;
    }
    if (!ext.empty()) {
        ext += ")";
    }
    return fmt::format("  {:<16} {}{}{}  {}{}{}\n", driver.GetDescription(), reads ? 'r' : '-', writes ? 'w' : '-',
                       writes && can_stream(driver) ? 's' : '-', name ? name : "", ext,
                       condition.empty() ? "" : " [" + condition + "]");
}

/// A flag that prints `text()` and ends the parse like --help does.
void add_printing_flag(CLI::App& app, const std::string& name, const std::string& help,
                       std::function<std::string()> text)
{
    app.add_flag_callback(name, [text] {
        std::cout << text();
        throw CLI::Success();
    }, help);
}

} // namespace

std::string version_text()
{
    return fmt::format("trisnap {} (build {})\n", k_version, build_id()) +
           fmt::format("GDAL {} (loaded), PROJ {}, GEOS {}\n", GDALVersionInfo("RELEASE_NAME"), proj_version(),
                       geos_version()) +
           fmt::format("CGAL {} (compiled in)\n", TRISNAP_CGAL_VERSION) +
           fmt::format("oneTBB {} (loaded)\n", TBB_runtime_version());
}

std::string formats_text()
{
    std::string out = fmt::format("Vector formats of GDAL {} here (r: IN can be one, w: OUT can be one, "
                                  "s: OUT can be - for stdout):\n", GDALVersionInfo("RELEASE_NAME"));
    GDALDriverManager* manager = GetGDALDriverManager();
    for (int i = 0; i < manager->GetDriverCount(); ++i) {
        GDALDriver* driver = manager->GetDriver(i);
        if (driver->GetMetadataItem(GDAL_DCAP_VECTOR)) {
            out += driver_line(*driver);
        }
    }
    return out;
}

void add_global_flags(CLI::App& app)
{
    add_printing_flag(app, "--version", "print the version of trisnap and of the libraries it runs with",
                      version_text);
    add_printing_flag(app, "--formats", "list the vector formats that can be read and written", formats_text);
    const CLI::App* root = &app;
    add_printing_flag(app, "--help-man", "", [root] { return man_page(*root); });
    add_printing_flag(app, "--completion-bash", "", [root] { return bash_completion(*root); });
    app.get_option("--help-man")->group("");
    app.get_option("--completion-bash")->group("");
}

} // namespace trisnap
