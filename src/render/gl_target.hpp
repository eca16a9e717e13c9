#pragma once
/// @file Off-screen render targets and tile read-back shared by the GL passes of baking.

#include "render/gl.hpp"

#include <cstddef>
#include <vector>

namespace crackle::render {

/// A framebuffer with colour attachments of the given formats (tile × tile) and optionally a
/// depth buffer; multisampled when samples > 1.
struct GlTarget {
    GLuint fbo = 0, depth = 0;
    std::vector<GLuint> color;
    int samples = 1;

    GlTarget(const std::vector<GLenum>& formats, int size, int samples, bool with_depth);
    ~GlTarget();
    GlTarget(const GlTarget&) = delete;
    GlTarget& operator=(const GlTarget&) = delete;
};

/// Copies a tile's rows into a full image of `image_width` × `image_height` pixels, flipping
/// GL's bottom-up rows to top-down; (tx, ty) is the tile's corner from the image's bottom left.
template <typename T>
void place_tile(std::vector<T>& image, int image_width, int image_height, int channels, const std::vector<T>& tile,
                int tile_size, int tx, int ty, int width, int height) {
    const auto c = static_cast<std::size_t>(channels);
    for (int y = 0; y < height; ++y) {
        const auto image_row = static_cast<std::size_t>(image_height - 1 - (ty + y));
        const T* from = &tile[static_cast<std::size_t>(y) * static_cast<std::size_t>(tile_size) * c];
        T* to = &image[(image_row * static_cast<std::size_t>(image_width) + static_cast<std::size_t>(tx)) * c];
        std::copy(from, from + static_cast<std::size_t>(width) * c, to);
    }
}

} // namespace crackle::render
