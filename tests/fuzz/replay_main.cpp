// Replays fuzz inputs without libFuzzer: each argument is a file or a directory of files, each
// file is passed once to LLVMFuzzerTestOneInput. A fuzz target reports a bug by crashing
// (abort, sanitizer, uncaught exception), so exit 0 means every input passed.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::filesystem::path> inputs_of(const std::filesystem::path& arg)
{
    std::vector<std::filesystem::path> files;
    if (!std::filesystem::is_directory(arg)) {
        files.push_back(arg);
        return files;
    }
    for (const auto& entry : std::filesystem::directory_iterator(arg)) {
        if (entry.is_regular_file()) {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        throw std::runtime_error(file.string() + ": cannot read");
    }
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

} // namespace

int main(int argc, char** argv)
{
    std::size_t count = 0;
    for (int i = 1; i < argc; ++i) {
        for (const std::filesystem::path& file : inputs_of(argv[i])) {
            const std::vector<std::uint8_t> bytes = read_bytes(file);
            std::cout << "replay " << file.filename().string() << " (" << bytes.size() << " bytes)\n";
            LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
            ++count;
        }
    }
    std::cout << count << " inputs replayed\n";
    if (count == 0) {
        std::cerr << "no input found: the corpus is missing\n";
        return 1;
    }
    return 0;
}
