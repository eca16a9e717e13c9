#include "render/relief.hpp"

#include "core/log.hpp"
#include "core/math.hpp"
#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <array>
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

/// Box sums of radius r down every column, a running sum per column over the rows (row-major:
/// cache friendly), wrapping in v on periodic surfaces, clamped at the ends otherwise. The
/// columns are split into blocks over the cores; each column's sums are the same either way.
void box_columns(const PixelGrid& g, std::vector<double>& values, int r) {
    const int w = g.width, h = g.height;
    r = std::min(r, (h - 1) / 2);
    const std::vector<double> in(values);
    auto row = [&](int y) {
        y = g.wrap_v ? ((y % h) + h) % h : std::clamp(y, 0, h - 1);
        return &in[g.index(0, y)];
    };
    const double inv = 1.0 / (2 * r + 1);
    const int block = std::max(16, w / 64), blocks = (w + block - 1) / block;
    parallel_rows(blocks, [&](int b) {
        const int x0 = b * block, x1 = std::min(w, x0 + block);
        std::vector<double> sum(static_cast<std::size_t>(x1 - x0), 0.0);
        for (int y = -r; y <= r; ++y) {
            const double* src = row(y);
            for (int x = x0; x < x1; ++x)
                sum[static_cast<std::size_t>(x - x0)] += src[x];
        }
        for (int y = 0; y < h; ++y) {
            double* dst = &values[g.index(0, y)];
            const double *add = row(y + r + 1), *sub = row(y - r);
            for (int x = x0; x < x1; ++x) {
                dst[x] = sum[static_cast<std::size_t>(x - x0)] * inv;
                sum[static_cast<std::size_t>(x - x0)] += add[x] - sub[x];
            }
        }
    });
}

/// The crack flag comes from an un-antialiased pass, so the step from a crack pixel to a lip
/// would alias (stair-stepped walls, jagged lines in the colour): pixels next to the crack's edge
/// get their height averaged over their 3 × 3 neighbourhood ([1 2 1]² / 16; wider would fill
/// in one-pixel cracks), and `coverage` becomes the 5 × 5 binomial average ([1 4 6 4 1]² / 256)
/// of the crack flag: a soft edge for the colour and the mask.
void antialias_crack_edges(const PixelGrid& g, const std::vector<std::uint8_t>& crack, Relief& r) {
    const std::vector<float> height(r.height);
    r.coverage.assign(g.pixels(), 0.0f);
    constexpr double WIDE[5] = {1, 4, 6, 4, 1}, NARROW[5] = {0, 1, 2, 1, 0};
    parallel_rows(g.height, [&](int y) {
        int rows[5];
        for (int k = 0; k < 5; ++k) {
            const int yy = y + k - 2;
            rows[k] = g.wrap_v ? (yy % g.height + g.height) % g.height : std::clamp(yy, 0, g.height - 1);
        }
        for (int x = 0; x < g.width; ++x) {
            double h = 0, c = 0, c3 = 0;
            for (int ky = 0; ky < 5; ++ky)
                for (int kx = 0; kx < 5; ++kx) {
                    const std::size_t j = g.index(((x + kx - 2) % g.width + g.width) % g.width, rows[ky]);
                    c += WIDE[kx] * WIDE[ky] / 256.0 * crack[j];
                    const double narrow = NARROW[kx] * NARROW[ky] / 16.0;
                    h += narrow * height[j];
                    c3 += narrow * crack[j];
                }
            const std::size_t i = g.index(x, y);
            r.coverage[i] = static_cast<float>(c);
            if (c3 > 0 && c3 < 1) r.height[i] = static_cast<float>(h);
        }
    });
}

} // namespace

/// The grid at half resolution (2 × 2 blocks); both sides must be even.
PixelGrid half_grid(const PixelGrid& g) {
    PixelGrid h;
    h.width = g.width / 2;
    h.height = g.height / 2;
    h.metres_v = 2 * g.metres_v;
    h.wrap_v = g.wrap_v;
    for (int y = 0; y < h.height; ++y)
        h.metres_u.push_back(g.metres_u[static_cast<std::size_t>(2 * y)]
                             + g.metres_u[static_cast<std::size_t>(2 * y + 1)]);
    return h;
}

/// 1 where any pixel of the 2 × 2 block is set.
std::vector<std::uint8_t> half_any(const PixelGrid& g, const std::vector<std::uint8_t>& mask) {
    std::vector<std::uint8_t> out(g.pixels() / 4, 0);
    const int w = g.width / 2;
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x)
            if (mask[g.index(x, y)]) out[static_cast<std::size_t>((y / 2) * w + x / 2)] = 1;
    return out;
}

/// Bilinear upsampling of a half-resolution map back onto `g` (wrapping like the map).
std::vector<float> upsample2(const PixelGrid& g, const std::vector<float>& small) {
    const int w = g.width / 2, h = g.height / 2;
    std::vector<float> out(g.pixels());
    parallel_rows(g.height, [&](int y) {
        const double sy = (y + 0.5) / 2 - 0.5;
        const int y0 = static_cast<int>(std::floor(sy));
        const double fy = sy - y0;
        auto row = [&](int r) { return g.wrap_v ? (r % h + h) % h : std::clamp(r, 0, h - 1); };
        const auto r0 = static_cast<std::size_t>(row(y0)), r1 = static_cast<std::size_t>(row(y0 + 1));
        for (int x = 0; x < g.width; ++x) {
            const double sx = (x + 0.5) / 2 - 0.5;
            const int x0 = static_cast<int>(std::floor(sx));
            const double fx = sx - x0;
            const auto c0 = static_cast<std::size_t>((x0 % w + w) % w),
                       c1 = static_cast<std::size_t>(((x0 + 1) % w + w) % w);
            auto at = [&](std::size_t r, std::size_t c) { return double(small[r * static_cast<std::size_t>(w) + c]); };
            out[g.index(x, y)] = static_cast<float>((1 - fy) * ((1 - fx) * at(r0, c0) + fx * at(r0, c1))
                                                    + fy * ((1 - fx) * at(r1, c0) + fx * at(r1, c1)));
        }
    });
    return out;
}

std::vector<float> upsample_cubic(const PixelGrid& coarse, const std::vector<float>& field, int k) {
    const int cw = coarse.width, ch = coarse.height, W = cw * k, H = ch * k;
    // The four weights of each of the k phases between coarse centres.
    std::vector<std::array<double, 4>> weights(static_cast<std::size_t>(k));
    std::vector<int> base(static_cast<std::size_t>(k));
    for (int f = 0; f < k; ++f) {
        const double at = (f + 0.5) / k - 0.5, t = at - std::floor(at);
        base[static_cast<std::size_t>(f)] = static_cast<int>(std::floor(at)) - 1;
        weights[static_cast<std::size_t>(f)] = {0.5 * (-t * t * t + 2 * t * t - t),
                                                0.5 * (3 * t * t * t - 5 * t * t + 2),
                                                0.5 * (-3 * t * t * t + 4 * t * t + t), 0.5 * (t * t * t - t * t)};
    }
    std::vector<float> rows(static_cast<std::size_t>(ch) * std::size_t(W)), out(std::size_t(W) * std::size_t(H));
    parallel_rows(ch, [&](int y) { // along u, every coarse row
        for (int x = 0; x < W; ++x) {
            const auto f = static_cast<std::size_t>(x % k);
            double v = 0;
            for (int m = 0; m < 4; ++m) {
                const int c = ((x / k + base[f] + m) % cw + cw) % cw;
                v += weights[f][static_cast<std::size_t>(m)] * field[coarse.index(c, y)];
            }
            rows[static_cast<std::size_t>(y) * std::size_t(W) + std::size_t(x)] = static_cast<float>(v);
        }
    });
    parallel_rows(H, [&](int y) { // along v
        const auto f = static_cast<std::size_t>(y % k);
        std::array<const float*, 4> line{};
        for (int m = 0; m < 4; ++m) {
            int c = y / k + base[f] + m;
            c = coarse.wrap_v ? (c % ch + ch) % ch : std::clamp(c, 0, ch - 1);
            line[static_cast<std::size_t>(m)] = &rows[static_cast<std::size_t>(c) * std::size_t(W)];
        }
        for (int x = 0; x < W; ++x) {
            double v = 0;
            for (std::size_t m = 0; m < 4; ++m)
                v += weights[f][m] * line[m][x];
            out[static_cast<std::size_t>(y) * std::size_t(W) + std::size_t(x)] = static_cast<float>(v);
        }
    });
    return out;
}

std::vector<float> blur(const PixelGrid& g, const std::vector<float>& values, double sigma_px) {
    const int r = static_cast<int>(std::lround(sigma_px));
    if (r < 1) return values;
    std::vector<double> a(values.begin(), values.end());
    for (int pass = 0; pass < 3; ++pass) {
        parallel_rows(g.height, [&](int y) {
            std::vector<double> tmp;
            box_line(&a[g.index(0, y)], g.width, r, true, tmp);
        });
        box_columns(g, a, r);
    }
    return std::vector<float>(a.begin(), a.end());
}

std::vector<float> masked_blur(const PixelGrid& g, const std::vector<float>& values,
                               const std::vector<std::uint8_t>& mask, double sigma_px) {
    const int r = static_cast<int>(std::lround(sigma_px));
    if (r < 1) return values;
    const int w = g.width, h = g.height;
    // Channel 0: value · mask, channel 1: mask.
    std::vector<double> a(g.pixels()), b(g.pixels());
    parallel_rows(h, [&](int y) {
        for (std::size_t i = g.index(0, y), end = i + static_cast<std::size_t>(w); i < end; ++i) {
            b[i] = mask[i] ? 1.0 : 0.0;
            a[i] = b[i] * values[i];
        }
    });
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
    parallel_rows(h, [&](int y) {
        for (std::size_t i = g.index(0, y), end = i + static_cast<std::size_t>(w); i < end; ++i)
            if (b[i] > 1e-6) out[i] = static_cast<float>(a[i] / b[i]);
    });
    return out;
}

PlateHeights plate_heights(const RasterLayers& layers, const std::vector<std::uint8_t>& plate, double sigma_px) {
    const PixelGrid& g = layers.grid;
    PlateHeights p;
    p.half = sigma_px >= 8.0 && g.width % 2 == 0 && g.height % 2 == 0;
    if (!p.half) {
        p.grid = g;
        p.mean = layers.height;
        p.any = plate;
        return p;
    }
    // Wide smoothing at half resolution: the plates' mean height over each 2 × 2 block.
    p.grid = half_grid(g);
    p.mean.assign(p.grid.pixels(), 0.0f);
    std::vector<float> count(p.grid.pixels(), 0.0f);
    parallel_rows(p.grid.height, [&](int cy) {
        for (int y = 2 * cy; y < 2 * cy + 2; ++y)
            for (int x = 0; x < g.width; ++x)
                if (plate[g.index(x, y)]) {
                    const std::size_t c = p.grid.index(x / 2, cy);
                    p.mean[c] += layers.height[g.index(x, y)];
                    count[c] += 1.0f;
                }
    });
    p.any.assign(p.grid.pixels(), 0);
    for (std::size_t c = 0; c < p.grid.pixels(); ++c) {
        p.any[c] = count[c] > 0;
        p.mean[c] = count[c] > 0 ? p.mean[c] / count[c] : 0.0f;
    }
    return p;
}

std::vector<float> smooth_plates(const PixelGrid& map, const PlateHeights& p, double sigma_px) {
    const double s = p.half ? sigma_px / 2 : sigma_px;
    std::vector<float> v = masked_blur(p.grid, p.mean, p.any, std::min(s, 0.25 * p.grid.height));
    return p.half ? upsample2(map, v) : v;
}

namespace {

/// A plate pixel's drop towards the cracks: each weight class's groove (reach and depth from its
/// weight, V-shaped or rounded by crack_shape) at the class's distance, combined smoothly.
inline double combined_drop(const std::vector<std::vector<float>>& distance, const std::vector<double>& class_weight,
                            std::size_t i, double top, double pixel, const ReliefOptions& o) {
    // The classes' drops combine by a log-mean-exp over 3 % of the layer: a hard maximum
    // leaves a crease where one class's groove overtakes another's. It lies between the
    // largest drop minus τ·ln(classes) and the largest, so never deeper than that.
    const double tau = std::max(0.03 * top, 1e-9);
    double sum = 0, largest = 0;
    std::array<double, 8> drops{};
    for (std::size_t k = 0; k < distance.size(); ++k) {
        const double dk = distance[k][i], w = class_weight[k];
        if (!std::isfinite(dk)) continue;
        const double reach = std::max({o.bevel, o.crack_width * w, 1.5 * pixel});
        double depth = o.bevel;
        if (o.crack_depth > 0) depth = std::max(depth, o.crack_depth * top * std::sqrt(w));
        depth = std::min(depth, top);
        const double t = 1.0 - std::min(dk / reach, 1.0); // 1 at the lip, 0 at full reach
        const double v_shape = t * t, rounded = 1.0 - std::sqrt(1.0 - t * t);
        drops[k] = depth * ((1.0 - o.crack_shape) * v_shape + o.crack_shape * rounded);
        largest = std::max(largest, drops[k]);
    }
    for (std::size_t k = 0; k < distance.size(); ++k)
        sum += std::exp((drops[k] - largest) / tau);
    const double drop =
        std::min(top, largest + tau * std::log(std::max(sum, 1.0)) - tau * std::log(double(distance.size())));
    return std::max(drop, 0.0);
}

} // namespace

Relief shape_relief(const RasterLayers& layers, const ReliefOptions& o) {
    const PixelGrid& g = layers.grid;
    const std::size_t px = g.pixels();
    Relief out;
    out.height.assign(px, 0.0f);
    out.groove.assign(px, 1.0f);
    out.age.assign(px, 1.0f);
    out.detail.assign(px, 0.0f);

    Timer timer;
    // === 1. The plates' height, smoothed over about a third of an element.
    std::vector<std::uint8_t> plate(px);
    for (std::size_t i = 0; i < px; ++i)
        plate[i] = !layers.crack[i];
    const double sigma_px = o.element_size > 0 ? 0.35 * o.element_size / g.metres_v : 0.0;
    const std::vector<float> smooth = smooth_plates(g, plate_heights(layers, plate, sigma_px), sigma_px);

    // === 2–3. Lips and curl from the distance to the cracks. A crack's groove reaches as far as
    // its weight says; taking only the nearest crack's weight would cut the grooves off along the
    // lines where the nearest crack changes (sharp-edged triangles at branches and tips). So the
    // weights are split into classes, class k holding the cracks of weight ≥ k / CLASSES with its
    // own distance field (its weight rounded up to the class's upper edge), and a pixel's drop
    // combines the classes' drops smoothly (below): continuous.
    // Grooves wider than 8 pixels are shaped from distances computed at half resolution (an
    // error under a pixel, 4× less work at 4096²); the class-0 field at full resolution still
    // gives the nearest crack (its age) and the curl's distance.
    constexpr int CLASSES = 4;
    const bool half = o.crack_width / CLASSES / g.metres_v >= 8.0 && g.width % 2 == 0 && g.height % 2 == 0;
    const PixelGrid coarse = half ? half_grid(g) : g;
    const DistanceField field = distance_transform(g, layers.crack, true);
    std::vector<std::vector<float>> distance;
    std::vector<double> class_weight;
    for (int k = 0; k < CLASSES; ++k) {
        const float threshold = static_cast<float>(double(k) / CLASSES);
        std::vector<std::uint8_t> source(px, 0);
        parallel_rows(g.height, [&](int y) {
            for (std::size_t i = g.index(0, y), end = i + static_cast<std::size_t>(g.width); i < end; ++i)
                source[i] = layers.crack[i] && layers.weight[i] >= threshold;
        });
        if (k > 0 && std::find(source.begin(), source.end(), 1) == source.end()) break;
        const double weight = double(k + 1) / CLASSES; // the class's upper edge: weight 1 reaches fully
        // Where two grooves meet, the distance has a crease (equal distance to both cracks) that
        // shades as a sharp spike; a blur over a quarter of the groove's reach rounds it off.
        const double sigma = std::min(0.25 * o.crack_width * weight / coarse.metres_v, 0.1 * coarse.height);
        if (half) {
            const std::vector<float> d = distance_transform(coarse, half_any(g, source), false).distance;
            distance.push_back(upsample2(g, blur(coarse, d, sigma)));
        } else {
            distance.push_back(blur(g, k == 0 ? field.distance : distance_transform(g, source, false).distance, sigma));
        }
        class_weight.push_back(weight);
    }
    const double t_fields = timer.seconds();
    const Detail detail = micro_relief(g, DetailOptions{o.fibre, o.flake, o.grit, o.seed});
    const double t_detail = timer.seconds();
    const double detail_depth = o.fibre.depth + o.flake.depth + o.grit.depth;
    out.flake = detail.flake;
    parallel_rows(g.height, [&](int y) {
        const double pixel = std::min(g.metres_u[static_cast<std::size_t>(y)], g.metres_v);
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            const std::uint32_t q = field.nearest[i];
            const bool has_crack = q != std::numeric_limits<std::uint32_t>::max();
            out.age[i] = has_crack ? layers.age[q] : 1.0f;
            double h = 0, groove = 1;
            // Lip lines (an open crack's edge, or the whole of a closed one) take the plates' drop at
            // distance 0, so the line and its neighbours agree; walls and floor go down by
            // crack_depth from their own simulated height (more for heavier cracks).
            const double pixel_depth = o.crack_depth * std::sqrt(double(layers.weight[i]));
            if (layers.crack[i] && layers.lip[i]) {
                const double top = smooth[i];
                h = top - std::min(top, std::max(o.bevel, pixel_depth * top));
            } else if (layers.crack[i]) {
                h = std::max(0.0, double(layers.height[i]) * (1.0 - pixel_depth));
            } else {
                const double top = smooth[i], d = field.distance[i];
                const double drop = combined_drop(distance, class_weight, i, top, pixel, o);
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
                out.detail[i] = static_cast<float>(detail.height[i] / detail_depth);
                h += detail.height[i] * std::min(1.0, h / detail_depth);
            }
            out.height[i] = static_cast<float>(std::max(0.0, h));
            out.groove[i] = static_cast<float>(std::clamp(groove, 0.0, 1.0));
        }
    });
    antialias_crack_edges(g, layers.crack, out);
    log::debug("relief: smoothing and distance fields ", t_fields, " s, micro-relief ", t_detail - t_fields,
               " s, profile ", timer.seconds() - t_detail, " s (", distance.size(), " weight classes, ",
               half ? "half" : "full", " resolution, detail step ", detail.step, ")");
    return out;
}

} // namespace crackle::render
