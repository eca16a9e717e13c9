#include "render/detail.hpp"

#include "core/parallel.hpp"
#include "render/noise.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

/// Whole cells of `size` metres across a tile `metres` long (at least one).
int cells_across(double metres, double size) {
    return std::max(1, static_cast<int>(std::lround(metres / std::max(size, 1e-9))));
}

Cells cells_of(const DetailLayer& layer, double tile_u, double tile_v) {
    return Cells{cells_across(tile_u, layer.size), cells_across(tile_v, layer.size * layer.stretch)};
}

/// Adds one noise layer to `out`: row(v) gives the row's evaluator, whose (u, flake) returns the
/// height (m) and may set the flake number. Evaluated every `step` pixels, step the largest of 4, 2, 1 that keeps six
/// samples across the layer's finest cell (`finest_px`) and divides the map exactly (so it tiles), then interpolated
/// bilinearly with wrapping (every layer is continuous, flakes included); heights fade with a short row near a sphere's
/// pole, where the texture-space noise would otherwise turn into steep streaks.
template <typename Eval>
void add_layer(const PixelGrid& g, double finest_px, bool flakes, Detail& out, const Eval& row) {
    int step = 1;
    for (int s : {4, 2})
        if (finest_px / s >= 6.0 && g.width % s == 0 && g.height % s == 0) {
            step = s;
            break;
        }
    out.step = std::max(out.step, step);
    const int cw = g.width / step, ch = g.height / step;
    std::vector<float> height(static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch));
    std::vector<float> flake(flakes ? height.size() : 0);
    parallel_rows(ch, [&](int cy) {
        auto eval = row(1.0 - (cy + 0.5) / ch);
        for (int cx = 0; cx < cw; ++cx) {
            const std::size_t i =
                static_cast<std::size_t>(cy) * static_cast<std::size_t>(cw) + static_cast<std::size_t>(cx);
            double f = 0.5;
            height[i] = static_cast<float>(eval((cx + 0.5) / cw, f));
            if (flakes) flake[i] = static_cast<float>(f);
        }
    });
    const double equator_u = *std::max_element(g.metres_u.begin(), g.metres_u.end());
    parallel_rows(g.height, [&](int y) {
        const double row_scale = g.metres_u[static_cast<std::size_t>(y)] / equator_u;
        const double sy = (y + 0.5) / step - 0.5;
        const int y0 = static_cast<int>(std::floor(sy));
        const double fy = sy - y0;
        const auto r0 = static_cast<std::size_t>((y0 % ch + ch) % ch);
        const auto r1 = static_cast<std::size_t>(((y0 + 1) % ch + ch) % ch);
        for (int x = 0; x < g.width; ++x) {
            const double sx = (x + 0.5) / step - 0.5;
            const int x0 = static_cast<int>(std::floor(sx));
            const double fx = sx - x0;
            const auto c0 = static_cast<std::size_t>((x0 % cw + cw) % cw);
            const auto c1 = static_cast<std::size_t>(((x0 + 1) % cw + cw) % cw);
            auto at = [&](std::size_t r, std::size_t c) {
                return double(height[r * static_cast<std::size_t>(cw) + c]);
            };
            const double h =
                (1 - fy) * ((1 - fx) * at(r0, c0) + fx * at(r0, c1)) + fy * ((1 - fx) * at(r1, c0) + fx * at(r1, c1));
            const std::size_t i = g.index(x, y);
            out.height[i] += static_cast<float>(row_scale * h);
            if (flakes) {
                auto fl = [&](std::size_t r, std::size_t c) {
                    return double(flake[r * static_cast<std::size_t>(cw) + c]);
                };
                out.flake[i] = static_cast<float>((1 - fy) * ((1 - fx) * fl(r0, c0) + fx * fl(r0, c1))
                                                  + fy * ((1 - fx) * fl(r1, c0) + fx * fl(r1, c1)));
            }
        }
    });
}

} // namespace

Detail micro_relief(const PixelGrid& g, const DetailOptions& o) {
    Detail out;
    out.height.assign(g.pixels(), 0.0f);
    out.flake.assign(g.pixels(), 0.5f);
    const double tile_u = g.metres_u[static_cast<std::size_t>(g.height / 2)] * g.width, tile_v = g.metres_v * g.height;
    // The finest cell of a layer's finest octave, in pixels.
    auto finest = [&](Cells c, int octaves) {
        const double scale = double(1 << (octaves - 1));
        return std::min(g.width / (c.u * scale), g.height / (c.v * scale));
    };
    if (o.fibre.depth > 0) {
        const Cells fibre = cells_of(o.fibre, tile_u, tile_v);
        add_layer(g, finest(fibre, 3), false, out, [&](double v) {
            return [&, noise = FbmRow(v, fibre, o.seed + 101u, 3)](double u, double&) mutable {
                const double n = noise(u);
                return o.fibre.depth * (1.0 - 2.0 * std::abs(2.0 * n - 1.0)); // ridged: thin raised fibres
            };
        });
    }
    if (o.flake.depth > 0) {
        const Cells flake = cells_of(o.flake, tile_u, tile_v), warp{flake.u * 2, flake.v * 2};
        add_layer(g, std::min(finest(warp, 3), finest(flake, 1)), true, out, [&](double v) {
            return [&, v, warp_u = FbmRow(v, warp, o.seed + 211u, 3),
                    warp_v = FbmRow(v, warp, o.seed + 223u, 3)](double u, double& id) mutable {
                // Warped so flake borders wander instead of running straight (Voronoi edges).
                const double wu = (warp_u(u) - 0.5) * 0.8 / flake.u;
                const double wv = (warp_v(u) - 0.5) * 0.8 / flake.v;
                const CellSample c = cellular(u + wu, v + wv, flake, o.seed + 202u);
                // Each flake a plateau at its own height, sinking to a common level at its border:
                // continuous (F2 − F1 is), so it can be interpolated from a coarse grid without steps.
                const double t = std::clamp((c.f2 - c.f1) / 0.3, 0.0, 1.0);
                const double ramp = t * t * (3.0 - 2.0 * t);
                id = 0.5 + (c.id - 0.5) * ramp;
                return o.flake.depth * (ramp * (0.6 + 0.4 * (2.0 * c.id - 1.0)) - 0.4);
            };
        });
    }
    if (o.grit.depth > 0) {
        const Cells grit = cells_of(o.grit, tile_u, tile_v);
        add_layer(g, finest(grit, 2), false, out, [&](double v) {
            return [&, noise = FbmRow(v, grit, o.seed + 303u, 2)](double u, double&) mutable {
                return o.grit.depth * (2.0 * noise(u) - 1.0);
            };
        });
    }
    return out;
}

} // namespace crackle::render
