#include "cli_support.hpp"

#include "problem_codes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <csignal>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace trisnap::test {
namespace fs = std::filesystem;

namespace {

std::string quote(const std::string& arg)
{
    std::string out = "'";
    for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string field_text(const OGRFeature& f, int i)
{
    if (!f.IsFieldSetAndNotNull(i)) return "<null>";
    const OGRFieldType type = f.GetFieldDefnRef(i)->GetType();
    if (type == OFTReal) {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.17g", f.GetFieldAsDouble(i));
        return buffer;
    }
    if (type == OFTInteger || type == OFTInteger64) return std::to_string(f.GetFieldAsInteger64(i));
    return f.GetFieldAsString(i);
}

OGRGeometry* fixture_geometry(const FixtureFeature& feature)
{
    OGRGeometry* g = nullptr;
    if (feature.wkt.empty()) return nullptr;
    OGRGeometryFactory::createFromWkt(feature.wkt.c_str(), nullptr, &g);
    if (g && feature.nan_coordinate && wkbFlatten(g->getGeometryType()) == wkbPolygon)
        g->toPolygon()->getExteriorRing()->setPoint(1, std::numeric_limits<double>::quiet_NaN(), 0.0);
    return g;
}

void create_fields(OGRLayer& layer)
{
    const std::pair<const char*, OGRFieldType> fields[] = {
        {"id", OFTInteger}, {"big", OFTInteger64}, {"area", OFTReal}, {"name", OFTString}, {"day", OFTDate}};
    for (const auto& [name, type] : fields) {
        OGRFieldDefn defn(name, type);
        ASSERT_EQ(layer.CreateField(&defn), OGRERR_NONE) << name;
    }
}

} // namespace

std::vector<std::string> RunOutput::err_lines() const
{
    std::vector<std::string> lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

TempDir::TempDir()
{
    std::string pattern = (fs::temp_directory_path() / "trisnap-cli-XXXXXX").string();
    m_path = mkdtemp(pattern.data());
}

TempDir::~TempDir()
{
    std::error_code ec;
    fs::remove_all(m_path, ec);
}

namespace {

std::string trisnap_exe()
{
    const char* other = std::getenv("TRISNAP_TEST_EXE");
    return other != nullptr && *other != '\0' ? other : TRISNAP_EXE;
}

/// In the child: limits, SIGXFSZ ignored (a write past the limit fails with EFBIG instead of
/// killing the process, as on a full disk), stdout and stderr to files, then exec.
[[noreturn]] void exec_limited(const std::vector<std::string>& argv, const Limits& limits, const std::string& out,
                               const std::string& err)
{
    std::signal(SIGXFSZ, SIG_IGN);
    const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err_fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in_fd = ::open("/dev/null", O_RDONLY);
    ::dup2(out_fd, 1);
    ::dup2(err_fd, 2);
    ::dup2(in_fd, 0);
    if (limits.file_size > 0) {
        const rlimit limit{static_cast<rlim_t>(limits.file_size), static_cast<rlim_t>(limits.file_size)};
        ::setrlimit(RLIMIT_FSIZE, &limit);
    }
    if (limits.address_space > 0) {
        const rlimit limit{static_cast<rlim_t>(limits.address_space), static_cast<rlim_t>(limits.address_space)};
        ::setrlimit(RLIMIT_AS, &limit);
    }
    std::vector<char*> pointers;
    for (const std::string& a : argv) {
        pointers.push_back(const_cast<char*>(a.c_str()));
    }
    pointers.push_back(nullptr);
    ::execv(pointers[0], pointers.data());
    ::_exit(127);
}

} // namespace

pid_t spawn_trisnap(const TempDir& dir, const std::vector<std::string>& args, const Limits& limits)
{
    std::vector<std::string> argv{trisnap_exe()};
    argv.insert(argv.end(), args.begin(), args.end());
    const std::string out = dir.path("stdout.txt");
    const std::string err = dir.path("stderr.txt");
    const pid_t pid = ::fork();
    if (pid == 0) {
        exec_limited(argv, limits, out, err);
    }
    return pid;
}

RunOutput wait_trisnap(const TempDir& dir, pid_t pid)
{
    int status = 0;
    ::waitpid(pid, &status, 0);
    RunOutput result;
    result.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = file_bytes(dir.path("stdout.txt"));
    result.err = file_bytes(dir.path("stderr.txt"));
    return result;
}

bool wait_until_stopped(pid_t pid)
{
    int status = 0;
    return ::waitpid(pid, &status, WUNTRACED) == pid && WIFSTOPPED(status);
}

ScopedEnv::ScopedEnv(const std::string& name, const std::string& value) : m_name(name)
{
    ::setenv(name.c_str(), value.c_str(), 1);
}

ScopedEnv::~ScopedEnv()
{
    ::unsetenv(m_name.c_str());
}

RunOutput run_trisnap_limited(const TempDir& dir, const std::vector<std::string>& args, const Limits& limits)
{
    return wait_trisnap(dir, spawn_trisnap(dir, args, limits));
}

void expect_error(const RunOutput& r, int code, const std::string& text)
{
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_EQ(r.out, "");
    ASSERT_EQ(r.err_lines().size(), 1u) << r.err;
    EXPECT_NE(r.err.find("trisnap: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
}

std::vector<std::string> leftovers(const std::string& dir)
{
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.find(".trisnap-tmp") != std::string::npos) {
            names.push_back(name);
        }
    }
    return names;
}

RunOutput run_trisnap(const TempDir& dir, const std::vector<std::string>& args)
{
    std::string command = quote(trisnap_exe());
    for (const auto& a : args) {
        command.append(" ").append(quote(a));
    }
    const std::string out = dir.path("stdout.txt");
    const std::string err = dir.path("stderr.txt");
    command.append(" >").append(quote(out)).append(" 2>").append(quote(err)).append(" </dev/null");
    const int status = std::system(command.c_str());
    RunOutput result;
    result.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = file_bytes(out);
    result.err = file_bytes(err);
    return result;
}

RunOutput run_trisnap_killed_when(const TempDir& dir, const std::vector<std::string>& args,
                                  const std::function<bool(const std::string&)>& stop, int signal)
{
    int pipe_fds[2];
    if (pipe(pipe_fds) != 0) {
        ADD_FAILURE() << "pipe failed";
        return {};
    }
    const std::string out = dir.path("stdout.txt");
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv{const_cast<char*>(TRISNAP_EXE)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        dup2(pipe_fds[1], STDERR_FILENO);
        close(pipe_fds[0]);
        close(pipe_fds[1]);
        if (!freopen(out.c_str(), "w", stdout) || !freopen("/dev/null", "r", stdin)) _exit(126);
        execv(TRISNAP_EXE, argv.data());
        _exit(127);
    }
    close(pipe_fds[1]);
    RunOutput result;
    std::string pending;
    bool killed = false;
    char buffer[4096];
    for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) > 0;) {
        result.err.append(buffer, static_cast<std::size_t>(n));
        pending.append(buffer, static_cast<std::size_t>(n));
        for (std::size_t eol; !killed && (eol = pending.find('\n')) != std::string::npos;) {
            const std::string line = pending.substr(0, eol);
            pending.erase(0, eol + 1);
            if (stop(line)) {
                kill(pid, signal);
                killed = true;
            }
        }
    }
    close(pipe_fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    result.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = file_bytes(out);
    return result;
}

std::string data_dir() { return TRISNAP_DATA_DIR; }
std::string configs_dir() { return TRISNAP_CONFIGS_DIR; }
bool exists(const std::string& path) { return fs::exists(path); }

void write_fixture(const std::string& path, const std::string& driver_name, const std::string& layer_name,
                   int epsg, OGRwkbGeometryType type, const std::vector<FixtureFeature>& features)
{
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
    ASSERT_NE(driver, nullptr) << driver_name;
    GDALDatasetUniquePtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(ds) << path;
    OGRSpatialReference srs;
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (epsg) srs.importFromEPSG(epsg);
    OGRLayer* layer = ds->CreateLayer(layer_name.c_str(), epsg ? &srs : nullptr, type, nullptr);
    ASSERT_NE(layer, nullptr);
    create_fields(*layer);
    for (const FixtureFeature& f : features) {
        OGRFeatureUniquePtr feature(OGRFeature::CreateFeature(layer->GetLayerDefn()));
        for (const auto& [name, value] : f.fields) feature->SetField(name.c_str(), value.c_str());
        feature->SetGeometryDirectly(fixture_geometry(f));
        ASSERT_EQ(layer->CreateFeature(feature.get()), OGRERR_NONE);
    }
}

std::string write_snapping_gpkg(const TempDir& dir, const std::string& name)
{
    const std::string path = dir.path(name);
    write_fixture(path, "GPKG", "parcels", 3857, wkbUnknown, snapping_fixture());
    return path;
}

std::vector<FixtureFeature> snapping_fixture()
{
    auto attrs = [](int id, const std::string& name) {
        return std::map<std::string, std::string>{{"id", std::to_string(id)},
                                                  {"big", std::to_string(10000000000LL + id)},
                                                  {"area", std::to_string(id * 1.25)},
                                                  {"name", name},
                                                  {"day", "2020-01-0" + std::to_string(1 + id % 9)}};
    };
    return {
        {"POLYGON ((0 0,10 0,10 10,0 10,0 0))", attrs(1, "Zürich")},
        {"POLYGON ((10.004 0,20 0,20 10,10.004 10,10.004 0))", attrs(2, "Ærøskøbing")},
        {"POLYGON ((0 10.003,10 10.003,10 20,0 20,0 10.003))", attrs(3, "plain")},
        {"POLYGON ((30 0,30.005 0,30.005 0.005,30 0.005,30 0))", attrs(4, "tiny")},
        {"MULTIPOLYGON (((40 0,50 0,50 10,40 10,40 0),(42 2,42 8,48 8,48 2,42 2)),((60 0,70 0,70 5,60 5,60 0)))", attrs(5, "with hole")},
        {"POLYGON ((0 30,10 30,10 40,0 40,0 30))", {{"id", "6"}}}, // nulls in most fields
    };
}

std::vector<ReadFeature> read_layer(const std::string& path, const std::string& layer_name,
                                    const std::vector<double>& bbox)
{
    GDALAllRegister();
    std::vector<ReadFeature> out;
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR));
    if (!ds) {
        ADD_FAILURE() << "cannot open " << path;
        return out;
    }
    OGRLayer* layer = layer_name.empty() ? ds->GetLayer(0) : ds->GetLayerByName(layer_name.c_str());
    if (!layer) {
        ADD_FAILURE() << "no layer " << layer_name << " in " << path;
        return out;
    }
    if (bbox.size() == 4) layer->SetSpatialFilterRect(bbox[0], bbox[1], bbox[2], bbox[3]);
    while (OGRFeatureUniquePtr f{layer->GetNextFeature()}) {
        ReadFeature r;
        r.fid = f->GetFID();
        for (int i = 0; i < f->GetFieldCount(); ++i) r.fields[f->GetFieldDefnRef(i)->GetNameRef()] = field_text(*f, i);
        const OGRGeometry* g = f->GetGeometryRef();
        r.has_geometry = g != nullptr && !g->IsEmpty();
        if (r.has_geometry) {
            r.valid = g->IsValid();
            r.wkt = g->exportToWkt();
        }
        out.push_back(std::move(r));
    }
    return out;
}

nlohmann::json read_json(const std::string& path)
{
    std::ifstream in(path);
    return nlohmann::json::parse(in, nullptr, false);
}

std::vector<std::int64_t> missing_but_reported(const nlohmann::json& report, const std::vector<ReadFeature>& output)
{
    std::set<std::int64_t> present;
    for (const ReadFeature& f : output) {
        auto it = f.fields.find("orig_fid");
        present.insert(it != f.fields.end() ? std::stoll(it->second) : f.fid);
    }
    std::set<std::int64_t> reported;
    for (const auto& p : report["problems"]) {
        const std::int64_t fid = p["fid"].get<std::int64_t>();
        if (!present.count(fid) && is_not_written_code(p["code"].get<int>())) {
            reported.insert(fid);
        }
    }
    return {reported.begin(), reported.end()};
}

std::string file_bytes(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

} // namespace trisnap::test
