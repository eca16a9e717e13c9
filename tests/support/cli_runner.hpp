#pragma once
/// @file Runs the crackle CLI in-process and captures its streams and exit code.

#include <filesystem>
#include <initializer_list>
#include <string>
#include <sys/types.h>
#include <vector>

namespace crackle::test {

struct CliResult {
    int code = -1;
    std::string out;
    std::string err;
};

CliResult run_cli(const std::vector<std::string>& args);

/// Starts the crackle executable in a process of its own with `extra_env` ("NAME=value") added,
/// its stdout and stderr going to `out_file` and `err_file` when given; returns its pid.
pid_t spawn_crackle(const std::vector<std::string>& args, const std::vector<std::string>& extra_env = {},
                    const std::filesystem::path& out_file = {}, const std::filesystem::path& err_file = {});

/// Runs the crackle executable in a process of its own and waits: for runs that may end the
/// process (a budget's hard stop), which run_cli would share with the test runner. `code` is the
/// exit status, or 128 + the signal.
CliResult run_crackle(const std::vector<std::string>& args, const std::vector<std::string>& extra_env = {});

/// A fresh, empty folder `name.pid` under the build tree's test-output/ (or the system temp folder).
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
