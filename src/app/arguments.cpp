#include "app/arguments.hpp"

#include "config/errors.hpp"

#include <cpl_conv.h>

#include <filesystem>
#include <map>

namespace trisnap {
namespace {

/// ogr2ogr's one-dash options and what they are called here.
const std::map<std::string, std::string>& ogr2ogr_spellings()
{
    static const std::map<std::string, std::string> spellings = {
        {"-nln", "--nln"},         {"-lco", "--lco"},         {"-dsco", "--dsco"},
        {"-oo", "--oo"},           {"-where", "--where"},     {"-select", "--select"},
        {"-overwrite", "--overwrite"}, {"-skipfailures", "--skipfailures"},
        {"-update", "--update"},   {"-append", "--append"},
        {"-progress", "--progress=always"},
    };
    return spellings;
}

bool ends_with(const std::string& text, const std::string& suffix)
{
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// `--config X` names our settings file when X is a file or looks like one.
bool is_settings_file(const std::string& value)
{
    std::error_code ec;
    return std::filesystem::is_regular_file(value, ec) || ends_with(value, ".toml");
}

class Rewriter {
public:
    Rewriter(int argc, char** argv) : m_in(argv, argv + argc) {}

    Arguments run()
    {
        while (m_next < m_in.size()) {
            rewrite(take());
        }
        return std::move(m_out);
    }

private:
    std::string take() { return m_in[m_next++]; }
    bool has_more() const { return m_next < m_in.size(); }

    void rewrite(const std::string& arg)
    {
        const auto& spellings = ogr2ogr_spellings();
        if (const auto it = spellings.find(arg); it != spellings.end()) {
            m_out.argv.push_back(it->second);
        } else if (arg == "-spat") {
            spatial_filter();
        } else if (arg == "--config") {
            config(has_more() ? take() : std::string());
        } else if (arg.rfind("--config=", 0) == 0) {
            config(arg.substr(9));
        } else {
            m_out.argv.push_back(arg);
        }
    }

    /// -spat xmin ymin xmax ymax -> --bbox xmin,ymin,xmax,ymax (checked by --bbox).
    void spatial_filter()
    {
        std::string box;
        for (int i = 0; i < 4; ++i) {
            if (!has_more()) {
                throw argument_error("-spat needs four numbers: -spat xmin ymin xmax ymax");
            }
            if (i > 0) {
                box += ',';
            }
            box += take();
        }
        m_out.argv.push_back("--bbox");
        m_out.argv.push_back(box);
    }

    void config(const std::string& first)
    {
        if (first.empty()) {
            throw argument_error("--config needs KEY VALUE (a GDAL option) or FILE.toml (our settings)");
        }
        if (is_settings_file(first)) {
            m_out.argv.push_back("--settings");
            m_out.argv.push_back(first);
            return;
        }
        if (const auto eq = first.find('='); eq != std::string::npos) {
            m_out.gdal_config.emplace_back(first.substr(0, eq), first.substr(eq + 1));
            return;
        }
        if (!has_more()) {
            throw argument_error("--config " + first + ": no value; GDAL options are --config KEY VALUE, "
                                 "settings files --settings FILE.toml");
        }
        m_out.gdal_config.emplace_back(first, take());
    }

    std::vector<std::string> m_in;
    std::size_t m_next = 0;
    Arguments m_out;
};

} // namespace

Arguments normalise_arguments(int argc, char** argv)
{
    return Rewriter(argc, argv).run();
}

void apply_gdal_config(const Arguments& arguments)
{
    for (const auto& [key, value] : arguments.gdal_config) {
        CPLSetConfigOption(key.c_str(), value.c_str());
    }
}

} // namespace trisnap
