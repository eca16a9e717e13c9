#pragma once
/// @file Ambient occlusion from the whole height map (horizon-based, shaders/ao.frag), so tiles
/// see across their borders and the map wraps like the texture.

#include "render/distance.hpp"

#include <string>
#include <vector>

namespace crackle::render {

struct AoOptions {
    double radius = 0.01; ///< m
    double strength = 1.0;
    int tile = 1024;
    std::string shader_dir;
};

/// 1 = open. Above 1024 px a side it is computed at half resolution and interpolated back up
/// (occlusion varies slowly next to the height itself; measured 1.8 → 0.5 s at 4096²).
std::vector<float> ambient_occlusion(const PixelGrid& grid, const std::vector<float>& height, const AoOptions& options);

} // namespace crackle::render
