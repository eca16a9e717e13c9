#include "support/cli_runner.hpp"

#include "app/cli.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace crackle::test {

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
    const std::filesystem::path dir = root / name;
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
