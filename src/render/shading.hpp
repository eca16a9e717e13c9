#pragma once
/// @file Normals, albedo, roughness and the crack mask from the shaped relief: normals by
/// central differences of the final height (smooth within plates, no facets); colour that
/// varies with height, groove depth, cavity (the occlusion map) and crack age, with subtle
/// per-piece variation.

#include "core/math.hpp"
#include "render/relief.hpp"

#include <cstdint>
#include <vector>

namespace crackle::render {

struct ShadingOptions {
    Vec3 color = Vec3(0.263273, 0.170645, 0.100482);       ///< plate tops (ridges), linear RGB
    Vec3 crack_color = Vec3(0.013412, 0.010023, 0.007194); ///< crack walls and floor, linear RGB
    double color_variation = 0.3;                          ///< per-piece brightness (and a little hue), 0..1
    double grain = 0.15;                                   ///< tiling colour grain, 0..1
    double grain_size = 0.02, grain_stretch = 1.0;
    double cavity = 0.5; ///< how much the occlusion darkens the albedo, 0..1
    double roughness = 0.85, roughness_variation = 0.1;
    std::uint32_t seed = 1;
    bool operator==(const ShadingOptions&) const = default; ///< every field: the options test compares whole structs
};

/// Unit normals in the texture frame (x = u, y = v, z up), 3 per pixel.
std::vector<float> normals_from_height(const PixelGrid& grid, const std::vector<float>& height);

struct Shading {
    std::vector<std::uint8_t> color; ///< 3 per pixel, sRGB
    std::vector<float> roughness;
    std::vector<float> mask; ///< 1 in cracks, falling to 0 up the grooves' sides
};

Shading shade(const RasterLayers& layers, const Relief& relief, const std::vector<float>& ao,
              const ShadingOptions& options);

} // namespace crackle::render
