#pragma once
/// @file The floor of a bake's GL work: what llvmpipe needs to fill the raster's targets and read
/// them back, without multisampling and without geometry (`crackle bench bake`, issue 15).

#include "render/gl_context.hpp"

namespace crackle::render {

/// Seconds to clear and fill, tile by tile, the same targets render/raster.cpp draws into (a
/// one-sample R32F height, an RGBA8 + RGBA32F label target with depth) with one full-viewport
/// triangle each, and to read all three back into full-size images: `width` × `height` pixels
/// in `tile`² tiles.
double fill_readback_floor(int width, int height, int tile, GlContext& context);

} // namespace crackle::render
