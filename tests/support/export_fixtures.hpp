#pragma once
/// @file The export tests' inputs and readers: a cracked plate and a cracked trunk as piece
/// meshes, small maps, the files of an export written to a folder, a glTF (.gltf + .bin or .glb)
/// parsed back without any glTF library, and the Khronos validator.

#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "io/mesh_files.hpp"
#include "post/pieces.hpp"
#include "support/cli_runner.hpp"
#include "support/cracked_plate.hpp"

#include <doctest/doctest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

namespace crackle::test {

/// The 0.2 m plate of cracked_plate (300 elements, fracture seed 4) as pieces; with shrink_top
/// the tops pull away from the cracks into V-grooves, without it every top is flat.
inline post::PieceMesh plate_pieces(double shrink_top) {
    post::PostOptions o;
    o.shrink_top = shrink_top;
    return post::build_pieces(cracked_plate(300, 4), o);
}

/// A trunk 0.3 m around and 0.3 m tall, shrinking like the plate, as pieces.
inline post::PieceMesh trunk_pieces() {
    LayerSpec spec;
    spec.kind = mesh::SurfaceKind::Cylinder;
    spec.size = Vec2(0.3, 0.3);
    spec.elements = 300;
    spec.shrinkage = {3e-4, 3e-4};
    Layer layer(spec);
    Rng rng(4, RngStream::Fracture);
    return post::build_pieces(fracture::run_fem_remove(*layer.model, fracture::FractureOptions{}, rng), {});
}

/// size × size maps with a little variation in every channel (so that the PNGs differ).
inline render::TextureSet small_maps(int size = 8) {
    render::TextureSet s;
    s.width = s.height_px = size;
    const std::size_t px = s.pixels();
    s.height_scale = 0.01;
    for (std::size_t i = 0; i < px; ++i) {
        const float t = float(i % 7) / 7.0f;
        s.height.push_back(0.01f * t);
        s.normal.insert(s.normal.end(), {0.1f * t, -0.1f * t, 1.0f});
        s.color.insert(s.color.end(), {std::uint8_t(100 + i % 50), 80, 60});
        s.ao.push_back(1.0f - 0.5f * t);
        s.roughness.push_back(0.6f + 0.3f * t);
        s.mask.push_back(t);
        s.id.insert(s.id.end(), {std::uint8_t(i % 3), 0, 0});
    }
    return s;
}

inline void write_files(const std::vector<io::OutputFile>& files) {
    for (const io::OutputFile& f : files)
        write_file_atomically(f.path, std::string_view(reinterpret_cast<const char*>(f.bytes.data()), f.bytes.size()));
}

inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A glTF read back by hand: its JSON and its one buffer.
struct GltfDoc {
    Json json;
    std::vector<std::uint8_t> bin;

    const Json& at(const char* array, double index) const {
        return json.find(array)->elements()[static_cast<std::size_t>(index)];
    }
    /// The values of a tightly packed accessor, as floats (indices too: they stay exact).
    std::vector<float> accessor(double index) const {
        const Json& a = at("accessors", index);
        const Json& view = at("bufferViews", a.find("bufferView")->as_number());
        const Json* view_offset = view.find("byteOffset"); // absent when 0
        const auto offset = view_offset ? static_cast<std::size_t>(view_offset->as_number()) : std::size_t{0};
        const auto length = static_cast<std::size_t>(view.find("byteLength")->as_number());
        const bool indices = a.find("componentType")->as_number() == 5125; // UNSIGNED_INT
        std::vector<float> out(length / 4);
        for (std::size_t i = 0; i < out.size(); ++i) {
            if (indices) {
                std::uint32_t u = 0;
                std::memcpy(&u, bin.data() + offset + 4 * i, 4);
                out[i] = static_cast<float>(u);
            } else {
                std::memcpy(&out[i], bin.data() + offset + 4 * i, 4);
            }
        }
        return out;
    }
};

/// Parses a .gltf (with its .bin beside it) or a .glb (JSON and BIN chunks).
inline GltfDoc read_gltf(const std::filesystem::path& path) {
    const std::vector<std::uint8_t> bytes = read_bytes(path);
    GltfDoc doc;
    if (path.extension() == ".glb") {
        REQUIRE(bytes.size() > 20);
        REQUIRE(std::memcmp(bytes.data(), "glTF", 4) == 0);
        std::uint32_t json_length = 0, bin_length = 0;
        std::memcpy(&json_length, bytes.data() + 12, 4);
        REQUIRE(std::memcmp(bytes.data() + 16, "JSON", 4) == 0);
        doc.json = Json::parse(std::string(bytes.begin() + 20, bytes.begin() + 20 + json_length), path.string());
        const std::size_t bin_chunk = 20 + json_length;
        std::memcpy(&bin_length, bytes.data() + bin_chunk, 4);
        REQUIRE(std::memcmp(bytes.data() + bin_chunk + 4, "BIN", 4) == 0);
        doc.bin.assign(bytes.begin() + long(bin_chunk) + 8, bytes.begin() + long(bin_chunk + 8 + bin_length));
    } else {
        doc.json = Json::parse(std::string(bytes.begin(), bytes.end()), path.string());
        const std::string uri = doc.at("buffers", 0).find("uri")->as_string();
        doc.bin = read_bytes(path.parent_path() / uri);
    }
    return doc;
}

/// Runs the Khronos validator; returns its first output line ("errors=0 warnings=0 ...") and
/// the rest in `details`, or "" when it is not installed.
inline std::string validate(const std::filesystem::path& file, std::string& details) {
    const std::filesystem::path modules = std::filesystem::path(CRACKLE_SOURCE_DIR) / ".tools" / "node_modules";
    const std::filesystem::path script =
        std::filesystem::path(CRACKLE_SOURCE_DIR) / "tests" / "tools" / "validate_gltf.js";
    if (!std::filesystem::exists(modules / "gltf-validator")) return "";
    const std::string cmd = "node '" + script.string() + "' '" + file.string() + "' '" + modules.string() + "' 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return "";
    char buf[4096];
    std::string out;
    while (fgets(buf, sizeof buf, pipe))
        out += buf;
    pclose(pipe);
    details = out;
    return out.substr(0, out.find('\n'));
}

/// validate(), skipping (or failing under CRACKLE_REQUIRE_VALIDATOR=1) without the validator.
/// @return false when skipped.
inline bool check_validator(const std::filesystem::path& file) {
    std::string details;
    const std::string summary = validate(file, details);
    if (summary.empty()) {
        const char* require = std::getenv("CRACKLE_REQUIRE_VALIDATOR");
        if (require && std::string(require) == "1") FAIL("gltf-validator is not installed (run scripts/setup)");
        MESSAGE("skipped: gltf-validator not installed in .tools/ (scripts/setup installs it)");
        return false;
    }
    CAPTURE(file);
    CHECK_MESSAGE(summary.rfind("errors=0 warnings=0", 0) == 0, details);
    return true;
}

} // namespace crackle::test
