#include "render/ao.hpp"

#include "render/gl.hpp"
#include "render/gl_program.hpp"
#include "render/gl_target.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

/// Bilinear resampling of a w × h map to W × H, wrapping in u (and v when wrap_v); texel
/// centres at (i + ½)/size.
std::vector<float> upsample(const std::vector<float>& small, int w, int h, int W, int H, bool wrap_v) {
    std::vector<float> out(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
    auto at = [&](int r, int c) {
        return static_cast<double>(
            small[static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + static_cast<std::size_t>(c)]);
    };
    for (int y = 0; y < H; ++y) {
        const double sy = (y + 0.5) * h / H - 0.5;
        const int y0 = static_cast<int>(std::floor(sy));
        const double fy = sy - y0;
        auto row = [&](int r) { return wrap_v ? (r % h + h) % h : std::clamp(r, 0, h - 1); };
        const int r0 = row(y0), r1 = row(y0 + 1);
        for (int x = 0; x < W; ++x) {
            const double sx = (x + 0.5) * w / W - 0.5;
            const int x0 = static_cast<int>(std::floor(sx));
            const double fx = sx - x0;
            const int c0 = (x0 % w + w) % w, c1 = ((x0 + 1) % w + w) % w;
            out[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)] =
                static_cast<float>((1 - fy) * ((1 - fx) * at(r0, c0) + fx * at(r0, c1))
                                   + fy * ((1 - fx) * at(r1, c0) + fx * at(r1, c1)));
        }
    }
    return out;
}

} // namespace

std::vector<float> ambient_occlusion(const PixelGrid& g, const std::vector<float>& height, const AoOptions& o) {
    const int W = g.width, H = g.height;
    std::vector<float> gl_rows(g.pixels()); // bottom-up for GL
    for (int y = 0; y < H; ++y)
        std::copy_n(&height[g.index(0, H - 1 - y)], W, &gl_rows[g.index(0, y)]);
    GLuint height_tex = 0;
    glGenTextures(1, &height_tex);
    glBindTexture(GL_TEXTURE_2D, height_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, W, H, 0, GL_RED, GL_FLOAT, gl_rows.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, g.wrap_v ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    const GlProgram program("ao", shader_source("fullscreen.vert", o.shader_dir),
                            shader_source("ao.frag", o.shader_dir), o.shader_dir, {"fullscreen.vert", "ao.frag"});
    const bool half = std::max(W, H) > 1024;
    const int w = half ? std::max(1, W / 2) : W, h = half ? std::max(1, H / 2) : H;
    const int tile = std::min(o.tile, std::max(w, h));
    GlTarget target({GL_R32F}, tile, 1, false);
    GLuint empty_vao = 0;
    glGenVertexArrays(1, &empty_vao);
    glBindVertexArray(empty_vao);
    glDisable(GL_DEPTH_TEST);
    glViewport(0, 0, tile, tile);
    program.use();
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, height_tex);
    program.set("u_height", 0);
    program.set("u_metres", Vec2(g.metres_u[static_cast<std::size_t>(H / 2)] * W, g.metres_v * H));
    program.set("u_radius", static_cast<float>(o.radius));
    program.set("u_strength", static_cast<float>(o.strength));
    std::vector<float> small(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 1.0f);
    std::vector<float> pixels(static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile));
    for (int ty = 0; ty * tile < h; ++ty)
        for (int tx = 0; tx * tile < w; ++tx) {
            const int x0 = tx * tile, y0 = ty * tile;
            program.set("u_tile",
                        Eigen::Vector4d(double(x0) / w, double(y0) / h, double(x0 + tile) / w, double(y0 + tile) / h));
            glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, target.fbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, tile, tile, GL_RED, GL_FLOAT, pixels.data());
            place_tile(small, w, h, 1, pixels, tile, x0, y0, std::min(tile, w - x0), std::min(tile, h - y0));
        }
    glDeleteVertexArrays(1, &empty_vao);
    glDeleteTextures(1, &height_tex);
    return half ? upsample(small, w, h, W, H, g.wrap_v) : small;
}

} // namespace crackle::render
