#pragma once
/// @file The GL part of baking: an orthographic render of texture space (u, v) with height as
/// depth, drawing wrapped copies across periodic borders so maps tile; the sphere renders to
/// an equirectangular map. What comes back is raw layers (the piece under each pixel, the
/// simulated height, where the cracks are and when they formed); render/relief and
/// render/shading turn them into the maps.

#include "post/pieces.hpp"
#include "render/distance.hpp"
#include "render/gl_context.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace crackle::render {

struct RasterOptions {
    int width = 2048, height = 2048; ///< pixels along u and v
    int samples = 4;                 ///< MSAA samples for the height (1 = none)
    int tile = 1024;                 ///< render tile (pixels per side)
    double crack_age = 0.6;          ///< how much finer the last cracks are than the first (0..1)
    std::uint32_t seed = 1;
    std::string shader_dir;
};

/// Per-pixel layers, row 0 at the top of the image (v = 1).
struct RasterLayers {
    PixelGrid grid;
    std::vector<float> height;       ///< anti-aliased simulated height before curl and lip rounding (m)
    std::vector<std::int32_t> label; ///< piece under the pixel; −1 on crack walls, floor and lips
    std::vector<std::uint8_t> crack; ///< 1 on crack walls, floor, lip lines and uncovered pixels
    std::vector<std::uint8_t> lip;   ///< 1 where a lip line was drawn (an open crack's edge, or a closed crack)
    std::vector<float> weight;       ///< crack pixels: 1 for the first, widest cracks, less for later ones
    std::vector<float> age;          ///< crack pixels: 1 = the first crack, 0 = the last
    std::vector<std::uint8_t> id;    ///< 3 per pixel: the _ID map's colour
    double render_seconds = 0, readback_seconds = 0;
};

/// Pixel geometry of a piece mesh's maps: metres per pixel (per row on the sphere).
PixelGrid pixel_grid(const post::PieceMesh& pieces, int width, int height);

RasterLayers rasterize(const post::PieceMesh& pieces, const RasterOptions& options, GlContext& context);

} // namespace crackle::render
