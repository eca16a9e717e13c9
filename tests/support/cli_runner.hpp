#pragma once
/// @file Runs the crackle CLI in-process and captures its streams and exit code.

#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace crackle::test {

struct CliResult {
    int code = -1;
    std::string out;
    std::string err;
};

CliResult run_cli(const std::vector<std::string>& args);

/// A fresh, empty folder under the build tree's test-output/ (or the system temp folder).
std::filesystem::path scratch_dir(const std::string& name);

/// Writes a text file and returns its path.
std::filesystem::path write_text(const std::filesystem::path& path, const std::string& text);

/// True when `s` holds `part` (messages in CLI tests).
inline bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

/// Reads a whole file ("" if missing).
std::string slurp(const std::filesystem::path& path);

} // namespace crackle::test
