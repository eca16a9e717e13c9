#pragma once
/// @file Text files compiled into the binary (cmake/crackle_embed.cmake): presets, shaders.

#include <string_view>
#include <vector>

namespace crackle {

struct EmbeddedFile {
    std::string_view name; ///< path relative to its folder, without extension ("bark/elm")
    std::string_view path; ///< path relative to its folder ("bark/elm.toml")
    std::string_view text;
};

namespace embedded {
/// presets/**/*.toml
const std::vector<EmbeddedFile>& presets();
/// shaders/*.vert, *.frag, *.glsl
const std::vector<EmbeddedFile>& shaders();
/// docs/benchmarks/reference.json: the speed-vs-accuracy study's reference
const std::vector<EmbeddedFile>& bench_files();
/// scripts/*.py: the study's chart script
const std::vector<EmbeddedFile>& scripts();
} // namespace embedded

} // namespace crackle
