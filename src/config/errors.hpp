#pragma once
// Typed errors that main() turns into one line on stderr and an exit code:
// argument_error and config_error exit 2 (the user can fix the command), io_error exits 1.
#include <stdexcept>
#include <string>

namespace trisnap {

/// A command-line value that cannot be used ("--tolerance must be > 0, got -1").
class argument_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A configuration file problem; what() reads "FILE:LINE: key 'k': reason".
class config_error : public std::runtime_error {
public:
    config_error(const std::string& file, long line, const std::string& key,
                 const std::string& reason);
    const std::string& file() const { return m_file; }
    long line() const { return m_line; }
    const std::string& key() const { return m_key; }

private:
    std::string m_file;
    long m_line = 0;
    std::string m_key;
};

} // namespace trisnap
