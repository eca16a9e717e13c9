#pragma once
/// @file Baked maps in memory (plain data: io writes them without touching GL).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace crackle::render {

/// Maps of width × height_px pixels in memory, row 0 at the top of the image (v = 1).
struct TextureSet {
    int width = 0, height_px = 0;
    /// Metres for a displacement value of 1: the tallest point. Heights span [0, height_scale]
    /// in the float map and in the 16-bit PNG alike (nothing clipped).
    double height_scale = 1;
    std::vector<float> height;       ///< metres above the background
    std::vector<float> normal;       ///< 3 per pixel, unit normals in the texture frame (x = u, y = v, z up)
    std::vector<std::uint8_t> color; ///< 3 per pixel, sRGB
    std::vector<float> ao;           ///< 1 = open
    std::vector<float> roughness;
    std::vector<float> mask;      ///< 1 = crack, falling to 0 up the grooves' sides
    std::vector<std::uint8_t> id; ///< 3 per pixel, a colour per piece, black on the crack floor
    double render_seconds = 0, readback_seconds = 0, ao_seconds = 0;

    std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height_px); }
};

} // namespace crackle::render
