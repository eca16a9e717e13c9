#pragma once
/// @file Baking a piece mesh into texture maps: an orthographic render of texture space
/// (u, v) with height as depth, drawing wrapped copies across periodic borders so maps tile;
/// the sphere bakes to an equirectangular map. Rendered in tiles with MSAA, read back to
/// memory; io/texture_set writes the files.

#include "core/math.hpp"
#include "post/pieces.hpp"
#include "render/gl_context.hpp"
#include "render/texture_set.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace crackle::render {

/// The [bake] preset section (plus what the CLI adds).
struct BakeOptions {
    int size = 2048; ///< pixels per side
    int samples = 4; ///< MSAA samples (1 = none)
    int tile = 1024; ///< render tile (pixels per side)
    /// Top surface albedo, linear RGB (the schema's bake.color, sRGB 0.55 0.45 0.35).
    Vec3 color = Vec3(0.263273, 0.170645, 0.100482);
    /// Crack walls and floor, linear RGB (the schema's bake.crack_color, sRGB 0.12 0.1 0.08).
    Vec3 crack_color = Vec3(0.013412, 0.010023, 0.007194);
    double color_variation = 0.3; ///< per-piece variation, 0..1
    double grain = 0.15;          ///< strength of the tiling surface grain in the albedo, 0..1
    double grain_size = 0.02;     ///< feature size of the grain along u (m)
    double grain_stretch = 1.0;   ///< how much longer grain features are along v (bark fibres)
    double roughness = 0.85;
    double roughness_variation = 0.1;
    double ao_radius = 0.0; ///< m; 0 = twice the layer's full height
    double ao_strength = 1.0;
    std::uint32_t seed = 1;
    std::string shader_dir; ///< read shaders from here instead of the embedded copies
};

TextureSet bake(const post::PieceMesh& pieces, const BakeOptions& options, GlContext& context);

} // namespace crackle::render
