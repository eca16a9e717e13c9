#pragma once
/// @file Baking a piece mesh into texture maps: render/raster draws texture space with GL,
/// render/relief shapes the height per pixel, render/ao occludes it, render/shading colours it;
/// io/texture_set writes the files.

#include "core/math.hpp"
#include "post/pieces.hpp"
#include "render/gl_context.hpp"
#include "render/relief.hpp"
#include "render/shading.hpp"
#include "render/texture_set.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace crackle::render {

/// The [bake] preset section (plus what the CLI adds).
struct BakeOptions {
    int width = 2048, height = 2048; ///< pixels along u and v
    int samples = 4;                 ///< MSAA samples (1 = none)
    int tile = 1024;                 ///< render tile (pixels per side)
    ShadingOptions shading;
    /// Lip rounding, crack grooves and micro-relief (post.curl/bevel are copied in from the
    /// piece mesh; element_size too).
    ReliefOptions relief;
    double crack_age = 0.6; ///< how much finer the last cracks are than the first, 0..1
    double ao_radius = 0.0; ///< m; 0 = twice the layer's full height
    double ao_strength = 1.0;
    std::uint32_t seed = 1;
    std::string shader_dir;                              ///< read shaders from here instead of the embedded copies
    bool operator==(const BakeOptions&) const = default; ///< every field: the options test compares whole structs
};

TextureSet bake(const post::PieceMesh& pieces, const BakeOptions& options, GlContext& context);

} // namespace crackle::render
