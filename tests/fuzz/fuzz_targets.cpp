#include "fuzz_targets.hpp"

#include "app/run/scene.hpp"
#include "core/error.hpp"
#include "fracture/pattern_file.hpp"
#include "io/preset.hpp"

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <unistd.h>
#include <vector>

namespace crackle::fuzz {

namespace {

/// One folder per process, in memory where there is /dev/shm.
const std::filesystem::path& scratch() {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path base = std::filesystem::exists("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                                               : std::filesystem::temp_directory_path();
        std::filesystem::path d = base / ("crackle-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

std::array<std::string, 3> split_parts(std::string_view text) {
    std::array<std::string, 3> parts;
    std::size_t part = 0, start = 0;
    while (part < 2) {
        const std::size_t at = text.find("\n--\n", start);
        if (at == std::string_view::npos) break;
        parts[part++] = std::string(text.substr(start, at - start));
        start = at + 4;
    }
    parts[part] = std::string(text.substr(start));
    return parts;
}

void write(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

} // namespace

int preset(const std::uint8_t* data, std::size_t size) {
    if (size > 64 * 1024) return 0; // presets are small; longer inputs only slow the search
    const auto parts = split_parts(std::string_view(reinterpret_cast<const char*>(data), size));
    write(scratch() / "main.toml", parts[0]);
    write(scratch() / "parent.toml", parts[1]);
    io::PresetRequest request;
    request.name_or_path = (scratch() / "main.toml").string();
    std::istringstream lines(parts[2]);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) request.overrides.push_back(line);
    try {
        const io::Preset p = io::load_preset(request);
        // A preset that loads must also make its scene (surface, fields) without failing.
        (void)app::make_scene(app::make_run_plan(p));
    } catch (const InputError&) {
        // The expected refusal of bad input.
    }
    return 0;
}

int pattern(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    const std::uint64_t sum = fracture::fnv1a64(bytes);
    for (int i = 0; i < 8; ++i)
        bytes.push_back(static_cast<char>((sum >> (8 * i)) & 0xff));
    try {
        (void)fracture::decode_pattern(bytes, "fuzz.crackle");
    } catch (const InputError&) {
    }
    return 0;
}

} // namespace crackle::fuzz
