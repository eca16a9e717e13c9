#pragma once
/// @file Baked maps in memory (plain data: io writes them without touching GL).

#include <cstdint>
#include <vector>

namespace crackle::render {

/// Maps in memory, row 0 at the top of the image (v = 1).
struct TextureSet {
    int size = 0;
    double height_scale = 1;         ///< metres for a displacement value of 1
    std::vector<float> height;       ///< size² metres above the background
    std::vector<float> normal;       ///< size²·3, unit normals in the texture frame (x = u, y = v, z up)
    std::vector<std::uint8_t> color; ///< size²·3, sRGB
    std::vector<float> ao;           ///< size², 1 = open
    std::vector<float> roughness;    ///< size²
    std::vector<float> mask;         ///< size², 1 = crack
    std::vector<std::uint8_t> id;    ///< size²·3, a colour per piece, black on the crack floor
    double render_seconds = 0, readback_seconds = 0, ao_seconds = 0;
};

} // namespace crackle::render
