#include "render/bake.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "render/gl.hpp"
#include "render/gl_program.hpp"

#include <array>

namespace crackle::render {

namespace {

/// Interleaved vertex of the bake pass.
struct GpuVertex {
    float u, v, height, nx, ny, nz, fragment, crack;
};

/// A triangle soup in texture space. On the sphere each triangle's u is unwrapped across the
/// date line, and a pole vertex takes the mean u of its triangle's other corners.
std::vector<GpuVertex> soup(const post::PieceMesh& pieces) {
    std::vector<GpuVertex> out;
    out.reserve(3 * pieces.triangles.size());
    for (const auto& tri : pieces.triangles) {
        std::array<post::PieceVertex, 3> c = {pieces.vertices[tri[0]], pieces.vertices[tri[1]],
                                              pieces.vertices[tri[2]]};
        if (!pieces.periodic) {
            for (std::size_t k = 1; k < 3; ++k) {
                if (c[k].uv.x() - c[0].uv.x() > 0.5) c[k].uv.x() -= 1.0;
                if (c[k].uv.x() - c[0].uv.x() < -0.5) c[k].uv.x() += 1.0;
            }
            for (std::size_t k = 0; k < 3; ++k) {
                if (c[k].uv.y() > 1e-6 && c[k].uv.y() < 1 - 1e-6) continue;
                double sum = 0;
                int n = 0;
                for (std::size_t j = 0; j < 3; ++j)
                    if (j != k) {
                        sum += c[j].uv.x();
                        ++n;
                    }
                c[k].uv.x() = sum / n;
            }
        }
        for (const auto& p : c)
            out.push_back({static_cast<float>(p.uv.x()), static_cast<float>(p.uv.y()), static_cast<float>(p.height),
                           static_cast<float>(p.normal.x()), static_cast<float>(p.normal.y()),
                           static_cast<float>(p.normal.z()), static_cast<float>(p.fragment + 1), p.crack});
    }
    return out;
}

GLuint make_texture(GLenum internal, int w, int h, int samples) {
    GLuint t = 0;
    glGenTextures(1, &t);
    if (samples > 1) {
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples, internal, w, h, GL_TRUE);
    } else {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexStorage2D(GL_TEXTURE_2D, 1, internal, w, h);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    return t;
}

/// A framebuffer with colour attachments of the given formats and a depth buffer.
struct Target {
    GLuint fbo = 0, depth = 0;
    std::vector<GLuint> color;
    int samples = 1;

    Target(const std::vector<GLenum>& formats, int size, int samples_, bool with_depth) : samples(samples_) {
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        std::vector<GLenum> buffers;
        for (std::size_t i = 0; i < formats.size(); ++i) {
            const GLuint t = make_texture(formats[i], size, size, samples);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i),
                                   samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, t, 0);
            color.push_back(t);
            buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
        }
        if (with_depth) {
            glGenRenderbuffers(1, &depth);
            glBindRenderbuffer(GL_RENDERBUFFER, depth);
            if (samples > 1)
                glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, size, size);
            else
                glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, size, size);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        }
        glDrawBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            throw NumericError("off-screen framebuffer incomplete (status 0x" + std::to_string(status) + ")");
    }
    ~Target() {
        glDeleteFramebuffers(1, &fbo);
        if (depth) glDeleteRenderbuffers(1, &depth);
        glDeleteTextures(static_cast<GLsizei>(color.size()), color.data());
    }
    Target(const Target&) = delete;
    Target& operator=(const Target&) = delete;
};

/// Copies a tile's rows into a full image, flipping GL's bottom-up rows to top-down.
template <typename T>
void place_tile(std::vector<T>& image, int size, int channels, const std::vector<T>& tile, int tile_size, int tx,
                int ty, int width, int height) {
    for (int y = 0; y < height; ++y) {
        const int gl_row = ty + y;               // from the bottom of the image
        const int image_row = size - 1 - gl_row; // from the top
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image[(static_cast<std::size_t>(image_row) * static_cast<std::size_t>(size)
                       + static_cast<std::size_t>(tx + x))
                          * static_cast<std::size_t>(channels)
                      + static_cast<std::size_t>(c)] =
                    tile[(static_cast<std::size_t>(y) * static_cast<std::size_t>(tile_size)
                          + static_cast<std::size_t>(x))
                             * static_cast<std::size_t>(channels)
                         + static_cast<std::size_t>(c)];
    }
}

Vec3 to_vec3(const std::array<float, 3>& a) {
    return Vec3(a[0], a[1], a[2]);
}

} // namespace

TextureSet bake(const post::PieceMesh& pieces, const BakeOptions& o, GlContext& context) {
    CRACKLE_ASSERT(o.size >= 1 && o.size <= context.max_texture_size(), "texture size " << o.size << " out of range");
    TextureSet set;
    set.size = o.size;
    const std::size_t px = static_cast<std::size_t>(o.size) * static_cast<std::size_t>(o.size);
    set.height.assign(px, 0.0f);
    set.normal.assign(3 * px, 0.0f);
    set.color.assign(3 * px, 0);
    set.ao.assign(px, 1.0f);
    set.roughness.assign(px, 0.0f);
    set.mask.assign(px, 0.0f);
    set.id.assign(3 * px, 0);
    const double max_height = std::max(pieces.max_height, 1e-6);
    set.height_scale = max_height;

    const int tile = std::min(o.tile, o.size);
    const int samples = std::max(1, std::min(o.samples, context.max_samples()));
    Timer render_timer;

    // === Geometry and programs
    const std::vector<GpuVertex> vertices = soup(pieces);
    GLuint vao = 0, vbo = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(GpuVertex)), vertices.data(),
                 GL_STATIC_DRAW);
    const auto stride = static_cast<GLsizei>(sizeof(GpuVertex));
    const int widths[] = {2, 1, 3, 1, 1};
    std::size_t offset = 0;
    for (GLuint i = 0; i < 5; ++i) {
        glEnableVertexAttribArray(i);
        glVertexAttribPointer(i, widths[i], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
        offset += static_cast<std::size_t>(widths[i]) * sizeof(float);
    }
    const GlProgram bake_program("bake", shader_source("bake.vert", o.shader_dir),
                                 shader_source("bake.frag", o.shader_dir), o.shader_dir);
    const GlProgram id_program("id", shader_source("bake.vert", o.shader_dir), shader_source("id.frag", o.shader_dir),
                               o.shader_dir);

    // Periodic copies: all 9 neighbours on a torus; across the date line on the sphere.
    std::vector<float> offsets;
    for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
            if (!pieces.periodic && dv != 0) continue;
            offsets.push_back(static_cast<float>(du));
            offsets.push_back(static_cast<float>(dv));
        }
    const auto instances = static_cast<GLsizei>(offsets.size() / 2);

    // Texture-space bounds of the geometry: a periodic copy is drawn into a tile only when it
    // can reach it (interior tiles draw one copy instead of nine).
    Vec2 lo(1e30, 1e30), hi(-1e30, -1e30);
    for (const GpuVertex& v : vertices) {
        lo = lo.cwiseMin(Vec2(v.u, v.v));
        hi = hi.cwiseMax(Vec2(v.u, v.v));
    }
    std::vector<float> tile_offsets;
    auto setup = [&](const GlProgram& prog, const Eigen::Vector4d& window) {
        tile_offsets.clear();
        for (GLsizei i = 0; i < instances; ++i) {
            const double du = offsets[static_cast<std::size_t>(2 * i)],
                         dv = offsets[static_cast<std::size_t>(2 * i + 1)];
            if (hi.x() + du < window[0] || lo.x() + du > window[2] || hi.y() + dv < window[1]
                || lo.y() + dv > window[3])
                continue;
            tile_offsets.push_back(static_cast<float>(du));
            tile_offsets.push_back(static_cast<float>(dv));
        }
        const auto count = static_cast<GLsizei>(tile_offsets.size() / 2);
        while (tile_offsets.size() < 18)
            tile_offsets.push_back(0.0f);
        prog.use();
        prog.set("u_max_height", static_cast<float>(max_height * 1.001));
        glUniform2fv(prog.uniform("u_offsets"), 9, tile_offsets.data());
        return count;
    };

    // === Render targets: height, normal, colour (sRGB), material; resolved copies; ID
    // Normals in 10 bits per channel: finer than the 8-bit maps they become, 4 bytes a sample.
    const std::vector<GLenum> formats = {GL_R32F, GL_RGB10_A2, GL_SRGB8_ALPHA8, GL_RGBA8};
    Target msaa(formats, tile, samples, true);
    std::unique_ptr<Target> resolved;
    if (samples > 1) resolved = std::make_unique<Target>(formats, tile, 1, false);
    Target id_target({GL_RGBA8}, tile, 1, true);

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glViewport(0, 0, tile, tile);

    const Vec3 crack_linear = o.crack_color;
    // Whole numbers of grain cells per tile, so the grain tiles with the maps.
    const Vec2 grain_cells(std::max(1.0, std::round(pieces.tile_size.x() / o.grain_size)),
                           std::max(1.0, std::round(pieces.tile_size.y() / (o.grain_size * o.grain_stretch))));
    const float clear_height[4] = {0, 0, 0, 1};
    const float clear_normal[4] = {0.5f, 0.5f, 1.0f, 1};
    const float clear_color[4] = {static_cast<float>(crack_linear.x()), static_cast<float>(crack_linear.y()),
                                  static_cast<float>(crack_linear.z()), 1};
    const float clear_material[4] = {1.0f, static_cast<float>(std::min(1.0, o.roughness + 0.15)), 0, 1};
    const float clear_id[4] = {0, 0, 0, 1};

    std::vector<float> tile_height(static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile));
    std::vector<std::uint32_t> tile_normal(tile_height.size());
    std::vector<std::uint8_t> tile_rgba(4 * tile_height.size());
    std::vector<std::uint8_t> tile_material(4 * tile_height.size());

    const int tiles = (o.size + tile - 1) / tile;
    Progress progress("bake", tiles * tiles);
    double readback = 0;
    for (int ty = 0; ty < tiles; ++ty)
        for (int tx = 0; tx < tiles; ++tx) {
            const int x0 = tx * tile, y0 = ty * tile;
            const int w = std::min(tile, o.size - x0), h = std::min(tile, o.size - y0);
            // The tile's texture-space window: tile pixels map to [x0, x0 + tile) / size.
            const Eigen::Vector4d window(double(x0) / o.size, double(y0) / o.size, double(x0 + tile) / o.size,
                                         double(y0 + tile) / o.size);
            // --- Main pass
            glBindFramebuffer(GL_FRAMEBUFFER, msaa.fbo);
            glClearBufferfv(GL_COLOR, 0, clear_height);
            glClearBufferfv(GL_COLOR, 1, clear_normal);
            glClearBufferfv(GL_COLOR, 2, clear_color);
            glClearBufferfv(GL_COLOR, 3, clear_material);
            glClear(GL_DEPTH_BUFFER_BIT);
            const GLsizei copies = setup(bake_program, window);
            bake_program.set("u_tile", window);
            bake_program.set("u_color", o.color);
            bake_program.set("u_crack_color", o.crack_color);
            bake_program.set("u_color_variation", static_cast<float>(o.color_variation));
            bake_program.set("u_roughness", static_cast<float>(o.roughness));
            bake_program.set("u_roughness_variation", static_cast<float>(o.roughness_variation));
            bake_program.set("u_seed", static_cast<unsigned>(o.seed));
            bake_program.set("u_grain", static_cast<float>(o.grain));
            bake_program.set("u_grain_cells", grain_cells);
            glDrawArraysInstanced(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()), copies);
            const Target& source = resolved ? *resolved : msaa;
            if (resolved) {
                glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa.fbo);
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved->fbo);
                for (GLenum i = 0; i < 4; ++i) {
                    glReadBuffer(GL_COLOR_ATTACHMENT0 + i);
                    const GLenum draw[4] = {GL_NONE, GL_NONE, GL_NONE, GL_NONE};
                    GLenum bufs[4];
                    std::copy(draw, draw + 4, bufs);
                    bufs[i] = GL_COLOR_ATTACHMENT0 + i;
                    glDrawBuffers(4, bufs);
                    glBlitFramebuffer(0, 0, tile, tile, 0, 0, tile, tile, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                }
                const GLenum all[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                       GL_COLOR_ATTACHMENT3};
                glDrawBuffers(4, all);
            }
            // --- ID pass (no anti-aliasing: one piece per texel)
            glBindFramebuffer(GL_FRAMEBUFFER, id_target.fbo);
            glClearBufferfv(GL_COLOR, 0, clear_id);
            glClear(GL_DEPTH_BUFFER_BIT);
            setup(id_program, window);
            id_program.set("u_tile", window);
            id_program.set("u_seed", static_cast<unsigned>(o.seed));
            glDrawArraysInstanced(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()), copies);

            // --- Read back
            Timer read_timer;
            glBindFramebuffer(GL_READ_FRAMEBUFFER, source.fbo);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, tile, tile, GL_RED, GL_FLOAT, tile_height.data());
            place_tile(set.height, o.size, 1, tile_height, tile, x0, y0, w, h);
            glReadBuffer(GL_COLOR_ATTACHMENT1);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV, tile_normal.data());
            std::vector<float> n3(3 * tile_height.size());
            for (std::size_t i = 0; i < tile_height.size(); ++i) {
                const std::uint32_t p = tile_normal[i];
                auto channel = [&](int shift) { return 2.0 * double((p >> shift) & 1023u) / 1023.0 - 1.0; };
                Vec3 n(channel(0), channel(10), channel(20));
                // MSAA averages normals at edges: renormalise.
                n = n.norm() > 1e-6 ? Vec3(n.normalized()) : Vec3::UnitZ();
                n3[3 * i] = static_cast<float>(n.x());
                n3[3 * i + 1] = static_cast<float>(n.y());
                n3[3 * i + 2] = static_cast<float>(n.z());
            }
            place_tile(set.normal, o.size, 3, n3, tile, x0, y0, w, h);
            glReadBuffer(GL_COLOR_ATTACHMENT2);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_BYTE, tile_rgba.data());
            std::vector<std::uint8_t> rgb(3 * tile_height.size());
            for (std::size_t i = 0; i < tile_height.size(); ++i)
                for (int c = 0; c < 3; ++c)
                    rgb[3 * i + static_cast<std::size_t>(c)] = tile_rgba[4 * i + static_cast<std::size_t>(c)];
            place_tile(set.color, o.size, 3, rgb, tile, x0, y0, w, h);
            glReadBuffer(GL_COLOR_ATTACHMENT3);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_BYTE, tile_material.data());
            std::vector<float> mask(tile_height.size()), rough(tile_height.size());
            for (std::size_t i = 0; i < tile_height.size(); ++i) {
                mask[i] = static_cast<float>(tile_material[4 * i]) / 255.0f;
                rough[i] = static_cast<float>(tile_material[4 * i + 1]) / 255.0f;
            }
            place_tile(set.mask, o.size, 1, mask, tile, x0, y0, w, h);
            place_tile(set.roughness, o.size, 1, rough, tile, x0, y0, w, h);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, id_target.fbo);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_BYTE, tile_rgba.data());
            for (std::size_t i = 0; i < tile_height.size(); ++i)
                for (int c = 0; c < 3; ++c)
                    rgb[3 * i + static_cast<std::size_t>(c)] = tile_rgba[4 * i + static_cast<std::size_t>(c)];
            place_tile(set.id, o.size, 3, rgb, tile, x0, y0, w, h);
            readback += read_timer.seconds();
            progress.update(ty * tiles + tx + 1);
        }
    glDeleteBuffers(1, &vbo);
    glDeleteVertexArrays(1, &vao);
    set.readback_seconds = readback;
    set.render_seconds = render_timer.seconds() - readback;

    // === Ambient occlusion from the whole height map (so tiles see across their borders).
    // Occlusion varies slowly next to the height itself: above 1024² it is computed at half
    // resolution and interpolated back up (a quarter of the cost; measured 1.8 → 0.5 s at 4096²).
    Timer ao_timer;
    {
        std::vector<float> gl_rows(px); // bottom-up for GL
        for (int y = 0; y < o.size; ++y)
            std::copy_n(&set.height[static_cast<std::size_t>(o.size - 1 - y) * static_cast<std::size_t>(o.size)],
                        o.size, &gl_rows[static_cast<std::size_t>(y) * static_cast<std::size_t>(o.size)]);
        GLuint height_tex = 0;
        glGenTextures(1, &height_tex);
        glBindTexture(GL_TEXTURE_2D, height_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, o.size, o.size, 0, GL_RED, GL_FLOAT, gl_rows.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, pieces.periodic ? GL_REPEAT : GL_CLAMP_TO_EDGE);
        const GlProgram ao_program("ao", shader_source("fullscreen.vert", o.shader_dir),
                                   shader_source("ao.frag", o.shader_dir), o.shader_dir);
        const int ao_size = o.size > 1024 ? o.size / 2 : o.size;
        const int ao_tile = std::min(tile, ao_size);
        Target ao_target({GL_R32F}, ao_tile, 1, false);
        GLuint empty_vao = 0;
        glGenVertexArrays(1, &empty_vao);
        glBindVertexArray(empty_vao);
        glDisable(GL_DEPTH_TEST);
        glViewport(0, 0, ao_tile, ao_tile);
        ao_program.use();
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, height_tex);
        ao_program.set("u_height", 0);
        ao_program.set("u_metres", pieces.tile_size);
        ao_program.set("u_radius", static_cast<float>(o.ao_radius > 0 ? o.ao_radius : 2.0 * max_height));
        ao_program.set("u_strength", static_cast<float>(o.ao_strength));
        std::vector<float> ao_small(static_cast<std::size_t>(ao_size) * static_cast<std::size_t>(ao_size), 1.0f);
        std::vector<float> ao_tile_pixels(static_cast<std::size_t>(ao_tile) * static_cast<std::size_t>(ao_tile));
        const int ao_tiles = (ao_size + ao_tile - 1) / ao_tile;
        for (int ty = 0; ty < ao_tiles; ++ty)
            for (int tx = 0; tx < ao_tiles; ++tx) {
                const int x0 = tx * ao_tile, y0 = ty * ao_tile;
                const int w = std::min(ao_tile, ao_size - x0), h = std::min(ao_tile, ao_size - y0);
                ao_program.set("u_tile",
                               Eigen::Vector4d(double(x0) / ao_size, double(y0) / ao_size,
                                               double(x0 + ao_tile) / ao_size, double(y0 + ao_tile) / ao_size));
                glBindFramebuffer(GL_FRAMEBUFFER, ao_target.fbo);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                glBindFramebuffer(GL_READ_FRAMEBUFFER, ao_target.fbo);
                glReadBuffer(GL_COLOR_ATTACHMENT0);
                glReadPixels(0, 0, ao_tile, ao_tile, GL_RED, GL_FLOAT, ao_tile_pixels.data());
                place_tile(ao_small, ao_size, 1, ao_tile_pixels, ao_tile, x0, y0, w, h);
            }
        if (ao_size == o.size) {
            set.ao = std::move(ao_small);
        } else {
            // Bilinear upsampling, wrapping like the texture (texel centres at (i + ½)/size).
            const bool wrap_v = pieces.periodic;
            for (int y = 0; y < o.size; ++y) {
                const double sy = (y + 0.5) * ao_size / o.size - 0.5;
                const int y0 = static_cast<int>(std::floor(sy));
                const double fy = sy - y0;
                auto row = [&](int r) {
                    return wrap_v ? (r % ao_size + ao_size) % ao_size : std::clamp(r, 0, ao_size - 1);
                };
                const int r0 = row(y0), r1 = row(y0 + 1);
                for (int x = 0; x < o.size; ++x) {
                    const double sx = (x + 0.5) * ao_size / o.size - 0.5;
                    const int x0 = static_cast<int>(std::floor(sx));
                    const double fx = sx - x0;
                    const int c0 = (x0 % ao_size + ao_size) % ao_size, c1 = ((x0 + 1) % ao_size + ao_size) % ao_size;
                    auto at = [&](int r, int c) {
                        return static_cast<double>(
                            ao_small[static_cast<std::size_t>(r) * static_cast<std::size_t>(ao_size)
                                     + static_cast<std::size_t>(c)]);
                    };
                    set.ao[static_cast<std::size_t>(y) * static_cast<std::size_t>(o.size)
                           + static_cast<std::size_t>(x)] =
                        static_cast<float>((1 - fy) * ((1 - fx) * at(r0, c0) + fx * at(r0, c1))
                                           + fy * ((1 - fx) * at(r1, c0) + fx * at(r1, c1)));
                }
            }
        }
        glDeleteVertexArrays(1, &empty_vao);
        glDeleteTextures(1, &height_tex);
    }
    set.ao_seconds = ao_timer.seconds();
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) throw NumericError("OpenGL error 0x" + std::to_string(err) + " while baking");
    log::debug("bake ", o.size, "²: render ", set.render_seconds, " s, readback ", set.readback_seconds, " s, AO ",
               set.ao_seconds, " s (", samples, " samples, ", tiles * tiles, " tiles)");
    (void)to_vec3;
    return set;
}

} // namespace crackle::render
