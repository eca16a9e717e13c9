#include "render/relief.hpp"

#include "core/math.hpp"
#include "core/parallel.hpp"
#include "render/noise.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

/// Box sums of radius r along a line of n values read and written with stride (wrapping, or
/// clamped at the ends), in place.
void box_line(double* line, int n, int r, bool wrap, std::vector<double>& tmp) {
    tmp.assign(line, line + n);
    r = std::min(r, (n - 1) / 2);
    auto at = [&](int i) {
        return wrap ? tmp[static_cast<std::size_t>(((i % n) + n) % n)]
                    : tmp[static_cast<std::size_t>(std::clamp(i, 0, n - 1))];
    };
    double sum = 0;
    for (int i = -r; i <= r; ++i)
        sum += at(i);
    const double inv = 1.0 / (2 * r + 1);
    for (int i = 0; i < n; ++i) {
        line[i] = sum * inv;
        sum += at(i + r + 1) - at(i - r);
    }
}

/// Box sums of radius r down every column at once, row by row (row-major: cache friendly):
/// a running sum per column, wrapping in v on periodic surfaces, clamped at the ends otherwise.
void box_columns(const PixelGrid& g, std::vector<double>& values, int r) {
    const int w = g.width, h = g.height;
    r = std::min(r, (h - 1) / 2);
    const std::vector<double> in(values);
    auto row = [&](int y) {
        y = g.wrap_v ? ((y % h) + h) % h : std::clamp(y, 0, h - 1);
        return &in[g.index(0, y)];
    };
    std::vector<double> sum(static_cast<std::size_t>(w), 0.0);
    for (int y = -r; y <= r; ++y) {
        const double* src = row(y);
        for (int x = 0; x < w; ++x)
            sum[static_cast<std::size_t>(x)] += src[x];
    }
    const double inv = 1.0 / (2 * r + 1);
    for (int y = 0; y < h; ++y) {
        double* dst = &values[g.index(0, y)];
        const double *add = row(y + r + 1), *sub = row(y - r);
        for (int x = 0; x < w; ++x) {
            dst[x] = sum[static_cast<std::size_t>(x)] * inv;
            sum[static_cast<std::size_t>(x)] += add[x] - sub[x];
        }
    }
}

/// The crack flag comes from an un-antialiased pass, so the step from a crack pixel to a lip
/// would alias (stair-stepped walls, jagged lines in the colour): pixels next to the crack's edge
/// get their height averaged over their 3 × 3 neighbourhood ([1 2 1]² / 16), and `coverage`
/// becomes the same average of the crack flag (a soft edge for the colour and the mask).
void antialias_crack_edges(const PixelGrid& g, const std::vector<std::uint8_t>& crack, Relief& r) {
    const std::vector<float> height(r.height);
    r.coverage.assign(g.pixels(), 0.0f);
    parallel_rows(g.height, [&](int y) {
        for (int x = 0; x < g.width; ++x) {
            double h = 0, c = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int yy = y + dy;
                    if (yy < 0 || yy >= g.height) {
                        if (!g.wrap_v)
                            yy = std::clamp(yy, 0, g.height - 1);
                        else
                            yy = (yy + g.height) % g.height;
                    }
                    const int xx = (x + dx + g.width) % g.width;
                    const double weight = (dx == 0 ? 2 : 1) * (dy == 0 ? 2 : 1) / 16.0;
                    h += weight * height[g.index(xx, yy)];
                    c += weight * crack[g.index(xx, yy)];
                }
            const std::size_t i = g.index(x, y);
            r.coverage[i] = static_cast<float>(c);
            if (c > 0 && c < 1) r.height[i] = static_cast<float>(h);
        }
    });
}

/// Whole cells of `size` metres across a tile `metres` long (at least one).
int cells_across(double metres, double size) {
    return std::max(1, static_cast<int>(std::lround(metres / std::max(size, 1e-9))));
}

} // namespace

std::vector<float> masked_blur(const PixelGrid& g, const std::vector<float>& values,
                               const std::vector<std::uint8_t>& mask, double sigma_px) {
    const int r = static_cast<int>(std::lround(sigma_px));
    if (r < 1) return values;
    const int w = g.width, h = g.height;
    // Channel 0: value · mask, channel 1: mask.
    std::vector<double> a(g.pixels()), b(g.pixels());
    for (std::size_t i = 0; i < g.pixels(); ++i) {
        b[i] = mask[i] ? 1.0 : 0.0;
        a[i] = b[i] * values[i];
    }
    for (int pass = 0; pass < 3; ++pass) {
        parallel_rows(h, [&](int y) {
            std::vector<double> tmp;
            box_line(&a[g.index(0, y)], w, r, true, tmp);
            box_line(&b[g.index(0, y)], w, r, true, tmp);
        });
        for (std::vector<double>* channel : {&a, &b})
            box_columns(g, *channel, r);
    }
    std::vector<float> out(values);
    for (std::size_t i = 0; i < g.pixels(); ++i)
        if (b[i] > 1e-6) out[i] = static_cast<float>(a[i] / b[i]);
    return out;
}

Relief shape_relief(const RasterLayers& layers, const ReliefOptions& o) {
    const PixelGrid& g = layers.grid;
    const std::size_t px = g.pixels();
    Relief out;
    out.height.assign(px, 0.0f);
    out.groove.assign(px, 1.0f);
    out.age.assign(px, 1.0f);
    out.detail.assign(px, 0.0f);
    out.flake.assign(px, 0.5f);

    // === 1. The plates' height, smoothed over about a third of an element.
    std::vector<std::uint8_t> plate(px);
    for (std::size_t i = 0; i < px; ++i)
        plate[i] = !layers.crack[i];
    const double sigma_px = o.element_size > 0 ? 0.35 * o.element_size / g.metres_v : 0.0;
    const std::vector<float> smooth = masked_blur(g, layers.height, plate, std::min(sigma_px, 0.25 * g.height));

    // === 2–3. Lips and curl from the distance to the cracks. A crack's groove reaches as far as
    // its weight says; taking only the nearest crack's weight would cut the grooves off along the
    // lines where the nearest crack changes (sharp-edged triangles at branches and tips). So the
    // weights are split into classes, class k holding the cracks of weight ≥ k / CLASSES with its
    // own distance field (rounded up to the class's upper edge), and a pixel's drop is the largest over the classes:
    // continuous.
    constexpr int CLASSES = 4;
    std::vector<DistanceField> fields;
    std::vector<double> class_weight;
    for (int k = 0; k < CLASSES; ++k) {
        const double threshold = double(k) / CLASSES;
        std::vector<std::uint8_t> source(px, 0);
        std::size_t count = 0;
        for (std::size_t i = 0; i < px; ++i)
            if (layers.crack[i] && layers.weight[i] >= threshold) {
                source[i] = 1;
                ++count;
            }
        if (k > 0 && count == 0) break;
        fields.push_back(distance_transform(g, source, k == 0));
        class_weight.push_back(double(k + 1) / CLASSES); // the class's upper edge: weight 1 reaches fully
    }
    // Where two grooves meet, the distance has a crease (equal distance to both cracks) that
    // shades as a sharp spike; a blur over a quarter of the groove's reach rounds it off.
    std::vector<std::vector<float>> distance(fields.size());
    const std::vector<std::uint8_t> everywhere(px, 1);
    for (std::size_t k = 0; k < fields.size(); ++k) {
        const double reach_px = o.crack_width * class_weight[k] / g.metres_v;
        distance[k] = masked_blur(g, fields[k].distance, everywhere, std::min(0.25 * reach_px, 0.1 * g.height));
    }
    const DistanceField& field = fields.front();
    const double detail_depth = o.fibre.depth + o.flake.depth + o.grit.depth;
    const Vec2 tile(g.metres_u[static_cast<std::size_t>(g.height / 2)] * g.width, g.metres_v * g.height);
    const Cells fibre_cells{cells_across(tile.x(), o.fibre.size),
                            cells_across(tile.y(), o.fibre.size * o.fibre.stretch)};
    const Cells flake_cells{cells_across(tile.x(), o.flake.size),
                            cells_across(tile.y(), o.flake.size * o.flake.stretch)};
    const Cells grit_cells{cells_across(tile.x(), o.grit.size), cells_across(tile.y(), o.grit.size * o.grit.stretch)};
    const double equator_u = *std::max_element(g.metres_u.begin(), g.metres_u.end());
    parallel_rows(g.height, [&](int y) {
        const double pixel = std::min(g.metres_u[static_cast<std::size_t>(y)], g.metres_v);
        // The noise is laid out in texture space; on the sphere a row near a pole is short, so
        // the detail there fades with the row's length instead of turning into steep streaks.
        const double row_scale = g.metres_u[static_cast<std::size_t>(y)] / equator_u;
        const double v = 1.0 - (y + 0.5) / g.height;
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            const std::uint32_t q = field.nearest[i];
            const bool has_crack = q != std::numeric_limits<std::uint32_t>::max();
            out.age[i] = has_crack ? layers.age[q] : 1.0f;
            double h = 0, groove = 1;
            if (layers.crack[i]) {
                h = std::max(0.0, double(layers.height[i]) * (1.0 - o.crack_depth * std::sqrt(layers.weight[i])));
            } else {
                const double top = smooth[i], d = field.distance[i];
                double drop = 0;
                for (std::size_t k = 0; k < fields.size(); ++k) {
                    const double dk = distance[k][i], w = class_weight[k];
                    if (!std::isfinite(dk)) continue;
                    const double reach = std::max({o.bevel, o.crack_width * w, 1.5 * pixel});
                    double depth = o.bevel;
                    if (o.crack_depth > 0) depth = std::max(depth, o.crack_depth * top * std::sqrt(w));
                    depth = std::min(depth, top);
                    const double t = 1.0 - std::min(dk / reach, 1.0); // 1 at the lip, 0 at full reach
                    const double v_shape = t * t, rounded = 1.0 - std::sqrt(1.0 - t * t);
                    drop = std::max(drop, depth * ((1.0 - o.crack_shape) * v_shape + o.crack_shape * rounded));
                }
                double lift = 0;
                if (o.curl > 0 && std::isfinite(d)) {
                    const double curl_reach = o.curl_width * top;
                    if (curl_reach > 0 && d < curl_reach) lift = o.curl * top * sqr(1.0 - d / curl_reach);
                }
                h = top - drop + lift;
                groove = top > 0 ? drop / top : 0.0;
            }
            // === 4. Micro-relief, attenuated near the ground so heights stay ≥ 0.
            if (detail_depth > 0) {
                const double u = (x + 0.5) / g.width;
                double detail = 0;
                if (o.fibre.depth > 0) {
                    const double n = fbm(u, v, fibre_cells, o.seed + 101u, 3);
                    detail += o.fibre.depth * (1.0 - 2.0 * std::abs(2.0 * n - 1.0));
                }
                if (o.flake.depth > 0) {
                    // Warped so flake borders wander instead of running straight (Voronoi edges).
                    const Cells warp_cells{flake_cells.u * 2, flake_cells.v * 2};
                    const double wu = (fbm(u, v, warp_cells, o.seed + 211u, 3) - 0.5) * 0.8 / flake_cells.u;
                    const double wv = (fbm(u, v, warp_cells, o.seed + 223u, 3) - 0.5) * 0.8 / flake_cells.v;
                    const CellSample c = cellular(u + wu, v + wv, flake_cells, o.seed + 202u);
                    const double edge = std::clamp((c.f2 - c.f1) / 0.15, 0.0, 1.0);
                    out.flake[i] = static_cast<float>(c.id);
                    detail += o.flake.depth * (0.7 * (2.0 * c.id - 1.0) + 0.3 * (2.0 * std::sqrt(edge) - 1.0));
                }
                if (o.grit.depth > 0) {
                    const double n = fbm(u, v, grit_cells, o.seed + 303u, 2);
                    detail += o.grit.depth * (2.0 * n - 1.0);
                }
                detail *= row_scale;
                out.detail[i] = static_cast<float>(detail / detail_depth);
                h += detail * std::min(1.0, h / detail_depth);
            }
            out.height[i] = static_cast<float>(std::max(0.0, h));
            out.groove[i] = static_cast<float>(std::clamp(groove, 0.0, 1.0));
        }
    });
    antialias_crack_edges(g, layers.crack, out);
    return out;
}

} // namespace crackle::render
