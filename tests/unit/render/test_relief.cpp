// The per-pixel relief of the maps (render/distance, render/noise, render/relief): the distance
// transform against brute force, tiling noise, grooves that follow the cracks' weights, heights in
// their documented range, and no facets inside plates.
#include "render/bake.hpp"
#include "render/distance.hpp"
#include "render/noise.hpp"
#include "render/raster.hpp"
#include "render/relief.hpp"
#include "render/shading.hpp"
#include "support/cracked_plate.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

using namespace crackle;
using render::PixelGrid;

namespace {

PixelGrid grid(int w, int h, double mu, double mv, bool wrap_v, bool sphere_rows = false) {
    PixelGrid g;
    g.width = w;
    g.height = h;
    g.metres_v = mv;
    g.wrap_v = wrap_v;
    for (int y = 0; y < h; ++y)
        g.metres_u.push_back(sphere_rows ? mu * std::max(0.05, std::sin(PI * (y + 0.5) / h)) : mu);
    return g;
}

/// Synthetic raster layers: a plate `top` metres high with the given crack pixels and weights.
render::RasterLayers plate(const PixelGrid& g, double top) {
    render::RasterLayers r;
    r.grid = g;
    r.height.assign(g.pixels(), static_cast<float>(top));
    r.label.assign(g.pixels(), 0);
    r.crack.assign(g.pixels(), 0);
    r.lip.assign(g.pixels(), 0);
    r.weight.assign(g.pixels(), 1.0f);
    r.age.assign(g.pixels(), 1.0f);
    r.id.assign(3 * g.pixels(), 0);
    return r;
}

void crack_column(render::RasterLayers& r, int x, float weight) {
    for (int y = 0; y < r.grid.height; ++y) {
        const std::size_t i = r.grid.index(x, y);
        r.crack[i] = 1;
        r.weight[i] = weight;
        r.label[i] = -1;
        r.height[i] = 0.0f;
    }
}

/// 99.9th percentile of the angle (degrees) between neighbouring normals, over pixels at least
/// `margin` pixels from any crack pixel.
double facet_angle(const PixelGrid& g, const std::vector<float>& normal, const std::vector<std::uint8_t>& crack,
                   int margin) {
    const render::DistanceField d = render::distance_transform(g, crack, false);
    std::vector<double> angles;
    for (int y = 0; y + 1 < g.height; ++y)
        for (int x = 0; x + 1 < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (!(d.distance[i] > margin * g.metres_v)) continue;
            const Vec3 n(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]);
            for (const std::size_t j : {g.index(x + 1, y), g.index(x, y + 1)}) {
                const Vec3 m(normal[3 * j], normal[3 * j + 1], normal[3 * j + 2]);
                angles.push_back(std::acos(std::clamp(n.dot(m), -1.0, 1.0)) * RAD_TO_DEG);
            }
        }
    REQUIRE(angles.size() > 1000);
    const auto k = angles.size() * 999 / 1000;
    std::nth_element(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(k), angles.end());
    return angles[k];
}

} // namespace

TEST_SUITE("render") {
    TEST_CASE("distance transform: exact against brute force, with wide and per-row pixels and wrapping") {
        std::mt19937 rng(7);
        for (int trial = 0; trial < 40; ++trial) {
            const int w = 5 + static_cast<int>(rng() % 40), h = 5 + static_cast<int>(rng() % 40);
            const bool wrap_v = trial % 2 == 0, sphere = trial % 3 == 0;
            const PixelGrid g = grid(w, h, 0.001 * (1 + rng() % 3), 0.001, wrap_v, sphere);
            std::vector<std::uint8_t> source(g.pixels(), 0);
            const int n = static_cast<int>(rng() % 6);
            for (int k = 0; k < n; ++k)
                source[rng() % g.pixels()] = 1;
            CAPTURE(trial);
            const render::DistanceField d = render::distance_transform(g, source);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    double best = std::numeric_limits<double>::infinity();
                    for (int sy = 0; sy < h; ++sy)
                        for (int sx = 0; sx < w; ++sx) {
                            if (!source[g.index(sx, sy)]) continue;
                            int dx = std::abs(x - sx), dy = std::abs(y - sy);
                            dx = std::min(dx, w - dx); // u always wraps
                            if (wrap_v) dy = std::min(dy, h - dy);
                            const double mu = g.metres_u[static_cast<std::size_t>(y)];
                            best = std::min(best, std::hypot(mu * dx, g.metres_v * dy));
                        }
                    const std::size_t i = g.index(x, y);
                    if (!std::isfinite(best)) {
                        REQUIRE(!std::isfinite(d.distance[i]));
                        continue;
                    }
                    REQUIRE(d.distance[i] == doctest::Approx(best).epsilon(1e-5));
                    REQUIRE(source[d.nearest[i]] == 1);
                }
        }
    }

    TEST_CASE("noise: value, fractal and cellular noise tile over whole cells") {
        const render::Cells cells{5, 3};
        for (double u = 0.013; u < 1; u += 0.097)
            for (double v = 0.021; v < 1; v += 0.089) {
                CHECK(render::value_noise(u + 1, v, cells, 3) == doctest::Approx(render::value_noise(u, v, cells, 3)));
                CHECK(render::fbm(u, v - 1, cells, 3) == doctest::Approx(render::fbm(u, v, cells, 3)));
                const auto a = render::cellular(u, v, cells, 3), b = render::cellular(u - 1, v + 1, cells, 3);
                CHECK(a.f1 == doctest::Approx(b.f1));
                CHECK(a.id == b.id);
                const double n = render::value_noise(u, v, cells, 3);
                CHECK(n >= 0.0);
                CHECK(n <= 1.0);
            }
        // Not a constant: different seeds and places differ.
        CHECK(render::value_noise(0.3, 0.3, cells, 1) != render::value_noise(0.3, 0.3, cells, 2));
    }

    TEST_CASE("noise: a row's fractal noise (FbmRow, per pixel and a whole row at once) is fbm() bit for bit") {
        for (const render::Cells cells : {render::Cells{5, 3}, render::Cells{1, 1}, render::Cells{37, 12}})
            for (int octaves : {1, 2, 4})
                for (double v : {0.0, 0.31, 0.999}) {
                    const int width = 333;
                    render::FbmRow row(v, cells, 11u, octaves);
                    std::vector<double> filled;
                    render::FbmRow(v, cells, 11u, octaves).fill(width, filled);
                    REQUIRE(filled.size() == std::size_t(width));
                    for (int x = 0; x < width; ++x) {
                        const double u = (x + 0.5) / width, expected = render::fbm(u, v, cells, 11u, octaves);
                        CAPTURE(x);
                        REQUIRE(row(u) == expected); // exactly: the maps must not move
                        REQUIRE(filled[std::size_t(x)] == expected);
                    }
                }
    }

    TEST_CASE("relief: a crack's groove reaches as far as its weight, and heights stay within [0, top]") {
        const PixelGrid g = grid(160, 32, 0.001, 0.001, true);
        render::RasterLayers layers = plate(g, 0.01);
        crack_column(layers, 40, 1.0f);  // a first, wide crack
        crack_column(layers, 120, 0.3f); // a late, fine one
        render::ReliefOptions o;
        o.crack_width = 0.012;
        o.crack_depth = 1.0;
        o.element_size = 0.004;
        const render::Relief r = render::shape_relief(layers, o);
        auto reach = [&](int x0) {
            int n = 0;
            for (int x = x0 + 1; x < x0 + 40; ++x)
                if (r.height[g.index(x, 10)] < 0.0095) ++n;
            return n;
        };
        CAPTURE(reach(40));
        CAPTURE(reach(120));
        CHECK(reach(40) >= 6);
        CHECK(reach(40) >= 2 * reach(120));
        for (float h : r.height) {
            REQUIRE(h >= 0.0f);
            REQUIRE(h <= 0.0100001f);
        }
        // The lip of the first crack goes down to the ground (crack_depth 1); the late one's less.
        CHECK(r.height[g.index(41, 10)] < r.height[g.index(121, 10)]);
        // With micro-relief on, heights still never go below the ground.
        o.grit.depth = 0.003;
        o.fibre.depth = 0.003;
        const render::Relief rough = render::shape_relief(layers, o);
        double spread = 0;
        for (std::size_t i = 0; i < rough.height.size(); ++i) {
            REQUIRE(rough.height[i] >= 0.0f);
            spread += std::abs(rough.height[i] - r.height[i]);
        }
        CHECK(spread / double(g.pixels()) > 1e-4);
    }

    TEST_CASE("bake: no facets inside plates (normals from the smoothed relief, not the triangles)") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        const auto pattern = test::cracked_plate(600, 3);
        REQUIRE(pattern.num_fragments > 5);
        post::PostOptions po;
        po.shrink_top = 0.08; // pillowed plates: a curved top over linear triangles
        const post::PieceMesh pieces = post::build_pieces(pattern, po);
        render::BakeOptions o;
        o.width = o.height = 256;
        const render::TextureSet set = render::bake(pieces, o, *gl);
        render::RasterOptions ro;
        ro.width = ro.height = 256;
        const render::RasterLayers layers = render::rasterize(pieces, ro, *gl);
        const double smooth = facet_angle(layers.grid, set.normal, layers.crack, 4);
        // Control: normals of the triangles' own (piecewise linear) heights show the facets.
        const double faceted =
            facet_angle(layers.grid, render::normals_from_height(layers.grid, layers.height), layers.crack, 4);
        CAPTURE(smooth);
        CAPTURE(faceted);
        CHECK(smooth < 0.6 * faceted);
        CHECK(smooth < 1.0);
        // The image passes split rows over threads: the maps do not depend on how many.
        ::setenv("CRACKLE_THREADS", "1", 1);
        const render::TextureSet one = render::bake(pieces, o, *gl);
        ::setenv("CRACKLE_THREADS", "3", 1);
        const render::TextureSet three = render::bake(pieces, o, *gl);
        ::unsetenv("CRACKLE_THREADS");
        CHECK(one.height == set.height);
        CHECK(three.height == set.height);
        CHECK(one.color == three.color);
        CHECK(one.normal == three.normal);
        CHECK(one.roughness == three.roughness);
        // One documented range: [0, height_scale], the tallest pixel at full scale.
        const float top = *std::max_element(set.height.begin(), set.height.end());
        CHECK(top == doctest::Approx(set.height_scale));
        CHECK(*std::min_element(set.height.begin(), set.height.end()) >= 0.0f);
    }
}
