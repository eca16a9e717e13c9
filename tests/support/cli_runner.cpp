#include "support/cli_runner.hpp"

#include "app/cli/cli.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace crackle::test {

pid_t spawn_crackle(const std::vector<std::string>& args, const std::vector<std::string>& extra_env,
                    const std::filesystem::path& out_file, const std::filesystem::path& err_file) {
    std::vector<std::string> all{CRACKLE_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_strings(extra_env);
    for (char** e = environ; *e; ++e) {
        const std::string entry = *e;
        const std::string name = entry.substr(0, entry.find('='));
        const bool replaced = std::any_of(extra_env.begin(), extra_env.end(), [&](const std::string& x) {
            return x.compare(0, name.size() + 1, name + "=") == 0;
        });
        if (!replaced) env_strings.push_back(entry);
    }
    std::vector<char*> envp;
    for (std::string& e : env_strings)
        envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!out_file.empty())
        posix_spawn_file_actions_addopen(&actions, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (!err_file.empty())
        posix_spawn_file_actions_addopen(&actions, 2, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, CRACKLE_BINARY, &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error(std::string("cannot start ") + CRACKLE_BINARY + ": " + std::strerror(rc));
    return pid;
}

CliResult run_crackle(const std::vector<std::string>& args, const std::vector<std::string>& extra_env) {
    const std::filesystem::path dir = scratch_dir("run-crackle");
    const pid_t pid = spawn_crackle(args, extra_env, dir / "out.txt", dir / "err.txt");
    int status = 0;
    ::waitpid(pid, &status, 0);
    CliResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(dir / "out.txt");
    r.err = slurp(dir / "err.txt");
    std::filesystem::remove_all(dir);
    return r;
}

CliResult run_cli(const std::vector<std::string>& args) {
    std::vector<const char*> argv{"crackle"};
    for (const auto& a : args)
        argv.push_back(a.c_str());
    std::ostringstream out, err;
    CliResult r;
    r.code = app::run(static_cast<int>(argv.size()), argv.data(), out, err);
    r.out = out.str();
    r.err = err.str();
    return r;
}

std::filesystem::path scratch_dir(const std::string& name) {
    const char* base = std::getenv("CRACKLE_TEST_OUTPUT");
    const std::filesystem::path root =
        base ? std::filesystem::path(base) : std::filesystem::temp_directory_path() / "crackle-tests";
    // One folder per process: ctest runs test cases in parallel processes, and a helper shared by
    // two test cases (the envelope's simulate) must not have one empty the other's folder.
    const std::filesystem::path dir = root / (name + "." + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path write_text(const std::filesystem::path& path, const std::string& text) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string slurp(const std::filesystem::path& path) {
    std::ifstream is(path, std::ios::binary);
    std::ostringstream ss;
    ss << is.rdbuf();
    return ss.str();
}

} // namespace crackle::test
