#include "render/shading.hpp"

#include "core/parallel.hpp"
#include "render/noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace crackle::render {

namespace {

double smoothstep(double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

/// Linear → 8-bit sRGB through a table of 4096 linear steps (finer than 8-bit sRGB's darkest
/// step, so every code is reachable).
class SrgbTable {
public:
    SrgbTable() {
        for (std::size_t k = 0; k < m_table.size(); ++k) {
            const double c = double(k) / double(m_table.size() - 1);
            const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
            m_table[k] = static_cast<std::uint8_t>(std::lround(s * 255.0));
        }
    }
    std::uint8_t operator()(double linear) const {
        const double c = std::clamp(linear, 0.0, 1.0);
        return m_table[static_cast<std::size_t>(std::lround(c * double(m_table.size() - 1)))];
    }

private:
    std::array<std::uint8_t, 4096> m_table{};
};

} // namespace

std::vector<float> normals_from_height(const PixelGrid& g, const std::vector<float>& height) {
    std::vector<float> n(3 * g.pixels());
    parallel_rows(g.height, [&](int y) {
        const int up = y > 0 ? y - 1 : (g.wrap_v ? g.height - 1 : y);
        const int down = y + 1 < g.height ? y + 1 : (g.wrap_v ? 0 : y);
        const int steps = (up != y ? 1 : 0) + (down != y ? 1 : 0);
        const double dv = g.metres_v * std::max(steps, 1);
        // On the sphere a row within a few pixels of a pole is almost no length at all: a pixel's
        // width there is floored at 15 % of its height, or any difference along the row (the pole
        // rows are filled column by column) would tilt the normals to the horizon (dark spots).
        const double du = 2.0 * std::max(g.metres_u[static_cast<std::size_t>(y)], 0.15 * g.metres_v);
        for (int x = 0; x < g.width; ++x) {
            const int left = x > 0 ? x - 1 : g.width - 1, right = x + 1 < g.width ? x + 1 : 0;
            // Row y − 1 is higher in v (row 0 is the top of the image, v = 1).
            const double dh_du = (height[g.index(right, y)] - height[g.index(left, y)]) / du;
            const double dh_dv = (height[g.index(x, up)] - height[g.index(x, down)]) / dv;
            const Vec3 normal = Vec3(-dh_du, -dh_dv, 1.0).normalized();
            for (int c = 0; c < 3; ++c)
                n[3 * g.index(x, y) + static_cast<std::size_t>(c)] = static_cast<float>(normal[c]);
        }
    });
    return n;
}

Shading shade(const RasterLayers& layers, const Relief& relief, const std::vector<float>& ao, const ShadingOptions& o) {
    const PixelGrid& g = layers.grid;
    Shading s;
    s.color.assign(3 * g.pixels(), 0);
    s.roughness.assign(g.pixels(), 0.0f);
    s.mask.assign(g.pixels(), 0.0f);
    float max_height = 1e-9f;
    for (float h : relief.height)
        max_height = std::max(max_height, h);
    const double tile_u = g.metres_u[static_cast<std::size_t>(g.height / 2)] * g.width;
    const Cells grain_cells{
        std::max(1, static_cast<int>(std::lround(tile_u / o.grain_size))),
        std::max(1, static_cast<int>(std::lround(g.metres_v * g.height / (o.grain_size * o.grain_stretch))))};
    const SrgbTable srgb8;
    parallel_rows(g.height, [&](int y) {
        const double v = 1.0 - (y + 0.5) / g.height;
        std::vector<double> grain_row, crack_row;
        FbmRow(v, grain_cells, o.seed).fill(g.width, grain_row);
        FbmRow(v, Cells{grain_cells.u * 2, grain_cells.v * 2}, o.seed + 7u, 2).fill(g.width, crack_row);
        int row_label = std::numeric_limits<int>::min();
        double r0 = 0.5, r1 = 0.5, r2 = 0.5;
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            const int label = layers.label[i];
            // Per-piece variation: mostly brightness, a little hue (tinted glass otherwise); the
            // piece's numbers kept while the row stays in it.
            if (label != row_label) {
                row_label = label;
                r0 = label >= 0 ? piece_random(label, 0u, o.seed) : 0.5;
                r1 = label >= 0 ? piece_random(label, 1u, o.seed) : 0.5;
                r2 = label >= 0 ? piece_random(label, 2u, o.seed) : 0.5;
            }
            const Vec3 tint = Vec3::Ones() + o.color_variation * 0.12 * Vec3(r1 - 0.5, r2 - 0.5, 0.5 - r1);
            const double brightness = 1.0 + 0.6 * o.color_variation * (r0 - 0.5);
            const double grain = 1.0 + o.grain * (2.0 * grain_row[static_cast<std::size_t>(x)] - 1.0);
            const double detail = relief.detail[i];
            // Ridges lighter than furrows: the top colour darkens a little with depth below the
            // tallest point and brightens on the micro-relief's raised parts.
            const double height = relief.height[i] / max_height;
            const double flake = 1.0 + 0.25 * o.color_variation * (relief.flake[i] - 0.5);
            const Vec3 top =
                o.color.cwiseProduct(tint) * brightness * grain * flake * (0.8 + 0.2 * height) * (1.0 + 0.2 * detail);
            // Cracks: darker with depth; a young crack's fresh walls a little lighter.
            const double age = relief.age[i];
            const Vec3 crack = o.crack_color * (1.0 + 0.35 * (1.0 - age)) * (0.7 + 0.3 * height)
                               * (1.0 + 0.5 * o.grain * (crack_row[static_cast<std::size_t>(x)] - 0.5));
            const double in_crack = std::max(double(relief.coverage[i]), smoothstep(0.15, 0.85, relief.groove[i]));
            const double cavity = 1.0 - o.cavity * (1.0 - ao[i]);
            const Vec3 albedo = ((1.0 - in_crack) * top + in_crack * crack) * cavity;
            for (int c = 0; c < 3; ++c)
                s.color[3 * i + static_cast<std::size_t>(c)] = srgb8(albedo[c]);
            s.mask[i] = static_cast<float>(in_crack);
            const double rough = o.roughness + o.roughness_variation * (r0 - 0.5) + 0.15 * in_crack - 0.05 * detail;
            s.roughness[i] = static_cast<float>(std::clamp(rough, 0.0, 1.0));
        }
    });
    return s;
}

} // namespace crackle::render
