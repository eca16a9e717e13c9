#include "render/raster.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "render/gl.hpp"
#include "render/gl_program.hpp"
#include "render/gl_target.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace crackle::render {

namespace {

/// Interleaved vertex of the bake passes.
struct GpuVertex {
    float u, v, height, fragment, crack, weight, age;
};
constexpr int ATTRIBUTE_WIDTHS[] = {2, 1, 1, 1, 1, 1};

/// Crack weights: 1 for the first cracks, down to 1 − crack_age for the last; scaled by the
/// square root of the simulated opening over its 90th percentile where openings were simulated.
struct Weights {
    double crack_age = 0;
    double opening_reference = 0; ///< 0: no simulated openings

    Weights(const post::PieceMesh& pieces, double crack_age_) : crack_age(crack_age_) {
        std::vector<float> openings;
        for (const auto& v : pieces.vertices)
            if (v.crack > 0.5f && v.crack_opening > 0) openings.push_back(v.crack_opening);
        if (openings.size() >= 4) {
            const auto k = openings.size() * 9 / 10;
            std::nth_element(openings.begin(), openings.begin() + static_cast<std::ptrdiff_t>(k), openings.end());
            opening_reference = openings[k];
        }
    }
    float operator()(const post::PieceVertex& v) const {
        double w = 1.0 - crack_age * v.crack_time;
        if (opening_reference > 0) w *= std::clamp(std::sqrt(v.crack_opening / opening_reference), 0.25, 1.0);
        return static_cast<float>(w);
    }
};

GpuVertex gpu(const post::PieceVertex& p, const Weights& weights) {
    return {static_cast<float>(p.uv.x()),
            static_cast<float>(p.uv.y()),
            static_cast<float>(p.base_height),
            static_cast<float>(p.fragment + 1),
            p.crack,
            weights(p),
            1.0f - p.crack_time};
}

/// Measures each corner's u from corner 0's side of the sphere's date line.
template <std::size_t N> void unwrap_date_line(std::array<post::PieceVertex, N>& c) {
    for (std::size_t k = 1; k < N; ++k) {
        if (c[k].uv.x() - c[0].uv.x() > 0.5) c[k].uv.x() -= 1.0;
        if (c[k].uv.x() - c[0].uv.x() < -0.5) c[k].uv.x() += 1.0;
    }
}

/// A triangle soup in texture space. On the sphere each triangle's u is unwrapped across the
/// date line, a pole vertex takes the mean u of its triangle's other corners, and a triangle
/// around a pole (its corners' longitudes wind once around) is left out: it has no image in the
/// equirectangular map, and the rows it would cover are filled from the nearest drawn row.
std::vector<GpuVertex> triangle_soup(const post::PieceMesh& pieces, const Weights& weights) {
    std::vector<GpuVertex> out;
    out.reserve(3 * pieces.triangles.size());
    for (const auto& tri : pieces.triangles) {
        std::array<post::PieceVertex, 3> c = {pieces.vertices[tri[0]], pieces.vertices[tri[1]],
                                              pieces.vertices[tri[2]]};
        if (!pieces.periodic) {
            double winding = 0;
            for (std::size_t k = 0; k < 3; ++k) {
                double d = c[(k + 1) % 3].uv.x() - c[k].uv.x();
                d -= std::round(d);
                winding += d;
            }
            if (std::abs(winding) > 0.5) continue;
            unwrap_date_line(c);
            for (std::size_t k = 0; k < 3; ++k) {
                if (c[k].uv.y() > 1e-6 && c[k].uv.y() < 1 - 1e-6) continue;
                c[k].uv.x() = 0.5 * (c[(k + 1) % 3].uv.x() + c[(k + 2) % 3].uv.x());
            }
        }
        for (const auto& p : c)
            out.push_back(gpu(p, weights));
    }
    return out;
}

/// The crack lips as line segments (drawn in the label pass only).
std::vector<GpuVertex> lip_lines(const post::PieceMesh& pieces, const Weights& weights) {
    std::vector<GpuVertex> out;
    out.reserve(2 * pieces.lips.size());
    for (const auto& lip : pieces.lips) {
        std::array<post::PieceVertex, 2> c = {pieces.vertices[lip[0]], pieces.vertices[lip[1]]};
        if (!pieces.periodic) unwrap_date_line(c);
        for (auto& p : c) {
            p.fragment = -1;
            p.crack = 2.0f; // a lip line (id.frag marks it apart from walls and floor)
            out.push_back(gpu(p, weights));
        }
    }
    return out;
}

/// A vertex array of `vertices` with the bake shaders' attribute layout.
struct GpuBuffer {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    explicit GpuBuffer(const std::vector<GpuVertex>& vertices) : count(static_cast<GLsizei>(vertices.size())) {
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(GpuVertex)), vertices.data(),
                     GL_STATIC_DRAW);
        std::size_t offset = 0;
        for (GLuint i = 0; i < std::size(ATTRIBUTE_WIDTHS); ++i) {
            glEnableVertexAttribArray(i);
            glVertexAttribPointer(i, ATTRIBUTE_WIDTHS[i], GL_FLOAT, GL_FALSE, static_cast<GLsizei>(sizeof(GpuVertex)),
                                  reinterpret_cast<const void*>(offset));
            offset += static_cast<std::size_t>(ATTRIBUTE_WIDTHS[i]) * sizeof(float);
        }
    }
    ~GpuBuffer() {
        glDeleteBuffers(1, &vbo);
        glDeleteVertexArrays(1, &vao);
    }
    GpuBuffer(const GpuBuffer&) = delete;
    GpuBuffer& operator=(const GpuBuffer&) = delete;
};

/// On the sphere the rows nearest the poles are not covered by any triangle (left-out pole
/// triangles); each column copies its nearest covered pixel into them, so a pole is neither
/// painted as crack nor left at height 0.
void fill_pole_rows(RasterLayers& r, const std::vector<std::uint8_t>& covered) {
    const PixelGrid& g = r.grid;
    auto copy = [&](std::size_t from, std::size_t to) {
        r.height[to] = r.height[from];
        r.label[to] = r.label[from];
        r.crack[to] = r.crack[from];
        r.lip[to] = r.lip[from];
        r.weight[to] = r.weight[from];
        r.age[to] = r.age[from];
        for (std::size_t c = 0; c < 3; ++c)
            r.id[3 * to + c] = r.id[3 * from + c];
    };
    // The nearest covered pixel down (step +1) or up (step −1) the column from `from`, preferring
    // a plate to a crack within an eighth of the map (a cap copied from a crack would be one).
    auto source = [&](int x, int from, int step) {
        int first = -1;
        for (int y = from, n = 0; y >= 0 && y < g.height && n <= g.height / 8; y += step) {
            if (!covered[g.index(x, y)]) continue;
            if (first < 0) first = y;
            if (!r.crack[g.index(x, y)]) return y;
            ++n;
        }
        return first;
    };
    for (int x = 0; x < g.width; ++x) {
        int top = 0;
        while (top < g.height && !covered[g.index(x, top)])
            ++top;
        if (top == g.height) continue;
        const int top_source = source(x, top, 1);
        for (int y = 0; y < top; ++y)
            copy(g.index(x, top_source), g.index(x, y));
        int bottom = g.height - 1;
        while (bottom > top && !covered[g.index(x, bottom)])
            --bottom;
        const int bottom_source = source(x, bottom, -1);
        for (int y = bottom + 1; y < g.height; ++y)
            copy(g.index(x, bottom_source), g.index(x, y));
    }
}

} // namespace

PixelGrid pixel_grid(const post::PieceMesh& pieces, int width, int height) {
    PixelGrid g;
    g.width = width;
    g.height = height;
    g.wrap_v = pieces.periodic;
    g.metres_v = pieces.tile_size.y() / height;
    g.metres_u.resize(static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        double scale = 1.0;
        if (!pieces.periodic) {
            // Equirectangular: a row at latitude φ is cos φ times as long as the equator.
            const double v = 1.0 - (y + 0.5) / height;
            scale = std::max(std::cos(PI * (v - 0.5)), 0.5 / height);
        }
        g.metres_u[static_cast<std::size_t>(y)] = pieces.tile_size.x() * scale / width;
    }
    return g;
}

namespace {

/// The periodic copies of the geometry a tile draws: all 9 neighbours on a torus, across the
/// date line on the sphere, each only where it can reach the tile (interior tiles draw one copy
/// instead of nine).
class Copies {
public:
    Copies(const std::vector<GpuVertex>& triangles, bool periodic, double max_height) : m_max_height(max_height) {
        for (int dv = -1; dv <= 1; ++dv)
            for (int du = -1; du <= 1; ++du)
                if (periodic || dv == 0) m_offsets.emplace_back(du, dv);
        for (const GpuVertex& v : triangles) {
            m_lo = m_lo.cwiseMin(Vec2(v.u, v.v));
            m_hi = m_hi.cwiseMax(Vec2(v.u, v.v));
        }
    }

    /// Makes `prog` current with the tile's uniforms and the offsets of the copies that reach
    /// `window`; returns their count.
    GLsizei use(const GlProgram& prog, const Eigen::Vector4d& window) const {
        std::vector<float> copies;
        for (const Vec2& off : m_offsets) {
            if (m_hi.x() + off.x() < window[0] || m_lo.x() + off.x() > window[2] || m_hi.y() + off.y() < window[1]
                || m_lo.y() + off.y() > window[3])
                continue;
            copies.push_back(static_cast<float>(off.x()));
            copies.push_back(static_cast<float>(off.y()));
        }
        const auto count = static_cast<GLsizei>(copies.size() / 2);
        copies.resize(18, 0.0f);
        prog.use();
        prog.set("u_tile", window);
        prog.set("u_max_height", static_cast<float>(m_max_height * 1.001));
        glUniform2fv(prog.uniform("u_offsets"), 9, copies.data());
        return count;
    }

private:
    std::vector<Vec2> m_offsets;
    Vec2 m_lo = Vec2(1e30, 1e30), m_hi = Vec2(-1e30, -1e30);
    double m_max_height;
};

/// A tile's place in the map: its corner and the pixels of it inside the map.
struct Tile {
    int x0, y0, w, h;
};

/// One tile's read-back pixels.
struct TileBuffers {
    std::vector<float> height, layers;
    std::vector<std::uint8_t> rgba;
};

/// Reads a rendered tile back (the resolved height; the label target's ID colour and layers)
/// into the full-size images.
void read_tile(const GlTarget& source, const GlTarget& label_target, int tile, const Tile& t, int width, int height,
               TileBuffers& buffers, RasterLayers& r, std::vector<float>& layers, std::vector<std::uint8_t>& rgba) {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, source.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, tile, tile, GL_RED, GL_FLOAT, buffers.height.data());
    place_tile(r.height, width, height, 1, buffers.height, tile, t.x0, t.y0, t.w, t.h);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, label_target.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, tile, tile, GL_RGBA, GL_UNSIGNED_BYTE, buffers.rgba.data());
    place_tile(rgba, width, height, 4, buffers.rgba, tile, t.x0, t.y0, t.w, t.h);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, tile, tile, GL_RGBA, GL_FLOAT, buffers.layers.data());
    place_tile(layers, width, height, 4, buffers.layers, tile, t.x0, t.y0, t.w, t.h);
}

/// The label target's layers decoded per pixel: piece label, crack and lip flags, crack weight
/// and age, the ID colour; `covered` where anything was drawn.
void decode_layers(const std::vector<float>& layers, const std::vector<std::uint8_t>& rgba, int width, int height,
                   std::vector<std::uint8_t>& covered, RasterLayers& r) {
    parallel_rows(height, [&](int y) {
        for (std::size_t i = std::size_t(y) * std::size_t(width), end = i + std::size_t(width); i < end; ++i) {
            const float label = layers[4 * i];
            covered[i] = label > -1.5f;
            r.label[i] = label > -0.5f ? static_cast<std::int32_t>(std::lround(label)) : -1;
            r.crack[i] = label < -0.5f || layers[4 * i + 1] > 0.5f;
            r.lip[i] = layers[4 * i + 1] > 1.5f;
            if (r.crack[i]) r.label[i] = -1;
            r.weight[i] = layers[4 * i + 2];
            r.age[i] = layers[4 * i + 3];
            for (std::size_t c = 0; c < 3; ++c)
                r.id[3 * i + c] = rgba[4 * i + c];
        }
    });
}

} // namespace

RasterLayers rasterize(const post::PieceMesh& pieces, const RasterOptions& o, GlContext& context) {
    CRACKLE_ASSERT(o.width >= 1 && o.height >= 1 && std::max(o.width, o.height) <= context.max_texture_size(),
                   "texture size " << o.width << "×" << o.height << " out of range");
    RasterLayers r;
    r.grid = pixel_grid(pieces, o.width, o.height);
    const std::size_t px = r.grid.pixels();
    r.height.assign(px, 0.0f);
    r.label.assign(px, -1);
    r.crack.assign(px, 1);
    r.lip.assign(px, 0);
    r.weight.assign(px, 1.0f);
    r.age.assign(px, 1.0f);
    r.id.assign(3 * px, 0);
    std::vector<std::uint8_t> covered(px, 0);

    const int tile = std::min(o.tile, std::max(o.width, o.height));
    const int samples = std::max(1, std::min(o.samples, context.max_samples()));
    Timer render_timer;
    const Weights weights(pieces, o.crack_age);
    const std::vector<GpuVertex> triangles = triangle_soup(pieces, weights);
    const std::vector<GpuVertex> lines = lip_lines(pieces, weights);
    const GpuBuffer triangle_buffer(triangles), line_buffer(lines);
    const GlProgram height_program("bake", shader_source("bake.vert", o.shader_dir),
                                   shader_source("bake.frag", o.shader_dir), o.shader_dir, {"bake.vert", "bake.frag"});
    const GlProgram label_program("id", shader_source("bake.vert", o.shader_dir),
                                  shader_source("id.frag", o.shader_dir), o.shader_dir, {"bake.vert", "id.frag"});
    const double max_height = std::max(pieces.max_height, 1e-6);

    const Copies copies_of(triangles, pieces.periodic, max_height);

    // === Targets: the height (multisampled, resolved); the labels (one piece per pixel)
    GlTarget msaa({GL_R32F}, tile, samples, true);
    std::unique_ptr<GlTarget> resolved;
    if (samples > 1) resolved = std::make_unique<GlTarget>(std::vector<GLenum>{GL_R32F}, tile, 1, false);
    GlTarget label_target({GL_RGBA8, GL_RGBA32F}, tile, 1, true);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glViewport(0, 0, tile, tile);
    const float clear_height[4] = {0, 0, 0, 1};
    const float clear_id[4] = {0, 0, 0, 1};
    const float clear_layers[4] = {-2, 1, 1, 1}; // label −2: nothing drawn here

    const auto tile_px = static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile);
    TileBuffers buffers{std::vector<float>(tile_px), std::vector<float>(4 * tile_px),
                        std::vector<std::uint8_t>(4 * tile_px)};
    std::vector<float> layers(4 * px, 0.0f);
    std::vector<std::uint8_t> rgba(4 * px, 0);

    const int tiles_x = (o.width + tile - 1) / tile, tiles_y = (o.height + tile - 1) / tile;
    Progress progress("bake", tiles_x * tiles_y);
    double readback = 0;
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            const int x0 = tx * tile, y0 = ty * tile;
            const int w = std::min(tile, o.width - x0), h = std::min(tile, o.height - y0);
            const Eigen::Vector4d window(double(x0) / o.width, double(y0) / o.height, double(x0 + tile) / o.width,
                                         double(y0 + tile) / o.height);
            // --- Height (anti-aliased)
            glBindFramebuffer(GL_FRAMEBUFFER, msaa.fbo);
            glClearBufferfv(GL_COLOR, 0, clear_height);
            glClear(GL_DEPTH_BUFFER_BIT);
            glEnable(GL_DEPTH_TEST);
            GLsizei copies = copies_of.use(height_program, window);
            glBindVertexArray(triangle_buffer.vao);
            glDrawArraysInstanced(GL_TRIANGLES, 0, triangle_buffer.count, copies);
            const GlTarget& source = resolved ? *resolved : msaa;
            if (resolved) {
                glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa.fbo);
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved->fbo);
                glBlitFramebuffer(0, 0, tile, tile, 0, 0, tile, tile, GL_COLOR_BUFFER_BIT, GL_NEAREST);
            }
            // --- Labels, crack flags and the ID colour (no anti-aliasing: one piece per pixel);
            // the lips on top, without depth test, so closed cracks still mark their pixels.
            glBindFramebuffer(GL_FRAMEBUFFER, label_target.fbo);
            glClearBufferfv(GL_COLOR, 0, clear_id);
            glClearBufferfv(GL_COLOR, 1, clear_layers);
            glClear(GL_DEPTH_BUFFER_BIT);
            copies = copies_of.use(label_program, window);
            label_program.set("u_seed", static_cast<unsigned>(o.seed));
            glDrawArraysInstanced(GL_TRIANGLES, 0, triangle_buffer.count, copies);
            glDisable(GL_DEPTH_TEST);
            glBindVertexArray(line_buffer.vao);
            glDrawArraysInstanced(GL_LINES, 0, line_buffer.count, copies);

            // --- Read back
            Timer read_timer;
            read_tile(source, label_target, tile, Tile{x0, y0, w, h}, o.width, o.height, buffers, r, layers, rgba);
            readback += read_timer.seconds();
            progress.update(ty * tiles_x + tx + 1);
        }
    decode_layers(layers, rgba, o.width, o.height, covered, r);
    if (!pieces.periodic) fill_pole_rows(r, covered);
    r.readback_seconds = readback;
    r.render_seconds = render_timer.seconds() - readback;
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR) throw NumericError("OpenGL error 0x" + std::to_string(err) + " while baking");
    log::debug("raster ", o.width, "×", o.height, ": render ", r.render_seconds, " s, readback ", readback, " s (",
               samples, " samples, ", tiles_x * tiles_y, " tiles)");
    return r;
}

} // namespace crackle::render
