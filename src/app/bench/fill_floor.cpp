#include "app/bench/fill_floor.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"
#include "render/gl_program.hpp"
#include "render/gl_target.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace crackle::render {

double fill_readback_floor(int width, int height, int tile, GlContext& context) {
    (void)context; // current on this thread
    tile = std::min(tile, std::max(width, height));
    const GlProgram program("floor", shader_source("fullscreen.vert"), R"(
uniform vec4 u_tile;
in vec2 v_uv;
layout(location = 0) out vec4 o_first;
layout(location = 1) out vec4 o_second;
void main()
{
    o_first = vec4(v_uv, 0.0, 1.0);
    o_second = vec4(v_uv, 1.0, 1.0);
}
)");
    GLuint empty_vao = 0;
    glGenVertexArrays(1, &empty_vao);
    Timer timer;
    GlTarget height_target({GL_R32F}, tile, 1, true);
    GlTarget label_target({GL_RGBA8, GL_RGBA32F}, tile, 1, true);
    const auto px = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const auto tile_px = static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile);
    std::vector<float> heights(px), layers(4 * px), tile_height(tile_px), tile_layers(4 * tile_px);
    std::vector<std::uint8_t> rgba(4 * px), tile_rgba(4 * tile_px);
    glViewport(0, 0, tile, tile);
    glEnable(GL_DEPTH_TEST);
    program.use();
    glBindVertexArray(empty_vao);
    const float zero[4] = {0, 0, 0, 1};
    const int tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            const int x0 = tx * tile, y0 = ty * tile;
            const int w = std::min(tile, width - x0), h = std::min(tile, height - y0);
            program.set("u_tile", Eigen::Vector4d(double(x0) / width, double(y0) / height, double(x0 + tile) / width,
                                                  double(y0 + tile) / height));
            for (const GlTarget* t : {&height_target, &label_target}) {
                glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
                for (GLint i = 0; i < static_cast<GLint>(t->color.size()); ++i)
                    glClearBufferfv(GL_COLOR, i, zero);
                glClear(GL_DEPTH_BUFFER_BIT);
                glDrawArrays(GL_TRIANGLES, 0, 3);
            }
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, height_target.fbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, tile, tile, GL_RED, GL_FLOAT, tile_height.data());
            place_tile(heights, width, height, 1, tile_height, tile, x0, y0, w, h);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, label_target.fbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_BYTE, tile_rgba.data());
            place_tile(rgba, width, height, 4, tile_rgba, tile, x0, y0, w, h);
            glReadBuffer(GL_COLOR_ATTACHMENT1);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_FLOAT, tile_layers.data());
            place_tile(layers, width, height, 4, tile_layers, tile, x0, y0, w, h);
        }
    const double seconds = timer.seconds();
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &empty_vao);
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) throw NumericError("OpenGL error 0x" + std::to_string(err) + " in the fill floor");
    return seconds;
}

} // namespace crackle::render
