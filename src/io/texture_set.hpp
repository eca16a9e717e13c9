#pragma once
/// @file Writing baked maps with ambientCG / Poly Haven names: <name>_Color.png,
/// _NormalGL.png, _NormalDX.png, _Displacement.png (16-bit), _AmbientOcclusion.png,
/// _Roughness.png, _Mask.png, _ID.png, and _Displacement.exr (32-bit float metres) on request.

#include "core/atomic_file.hpp"
#include "render/texture_set.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace crackle::io {

struct EncodedMap {
    std::string suffix;    ///< "Color", "NormalGL", ... ("ORM" for glTF's packed map)
    std::string extension; ///< "png" or "exr"
    std::vector<std::uint8_t> bytes;
};

/// Encodes every map (PNG; EXR when asked). Returns them with the encoding time.
std::vector<EncodedMap> encode_texture_set(const render::TextureSet& set, bool exr, double* seconds = nullptr);

/// One PNG map by its suffix ("Color", "NormalGL", "Roughness", ..., or "ORM"), with the bytes
/// encode_texture_set gives it.
EncodedMap encode_map(const render::TextureSet& set, const std::string& suffix);

/// glTF's packed occlusion (R), roughness (G), metallic (B = 0) map.
EncodedMap encode_orm(const render::TextureSet& set);

/// "<dir>/<name>_<suffix>.<ext>"
std::filesystem::path map_path(const std::filesystem::path& dir, const std::string& name, const EncodedMap& map);

/// 32-bit float single-channel EXR ("Y") of a width × height image, row 0 at the top.
std::vector<std::uint8_t> encode_exr_gray(const std::vector<float>& pixels, int width, int height);

/// Reads an EXR written by encode_exr_gray (for round-trip tests): its width, and its rows.
std::vector<float> decode_exr_gray(const std::vector<std::uint8_t>& bytes, int& width, int* rows = nullptr);

} // namespace crackle::io
