#include "fracture/fem_remove/fem_remove.hpp"
#include "fracture/toolkit/fem_pattern.hpp"
#include "io/png.hpp"
#include "io/texture_set.hpp"
#include "render/bake.hpp"
#include "render/gl_program.hpp"
#include "support/cracked_plate.hpp"
#include "support/fem_fixture.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>

using namespace crackle;

namespace {

/// An uncracked layer: the pattern of a model that never broke.
fracture::CrackPattern intact_pattern(const test::LayerSpec& spec) {
    test::Layer layer(spec);
    layer.model->relax();
    return fracture::pattern_from_model(*layer.model, "intact", layer.model->mesh().num_faces());
}

render::BakeOptions small(int size) {
    render::BakeOptions o;
    o.width = o.height = size;
    o.tile = 32; // several tiles even at test sizes, so tile borders are exercised
    return o;
}

const io::EncodedMap& find_map(const std::vector<io::EncodedMap>& maps, const std::string& suffix) {
    for (const auto& m : maps)
        if (m.suffix == suffix && m.extension == "png") return m;
    FAIL("no map " << suffix);
    return maps.front();
}

} // namespace

TEST_SUITE("render") {
    TEST_CASE("bake: a single flat piece gives constant height and the normal 0.5 0.5 1") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        test::LayerSpec spec;
        spec.elements = 200;
        spec.thickness = 0.012;
        const auto pieces = post::build_pieces(intact_pattern(spec), post::PostOptions{});
        CHECK(pieces.fragments == 1);
        CHECK(pieces.wall_triangles == 0);
        const render::TextureSet set = render::bake(pieces, small(64), *gl);
        for (std::size_t i = 0; i < set.height.size(); ++i) {
            REQUIRE(set.height[i] == doctest::Approx(0.012).epsilon(1e-6));
            REQUIRE(set.mask[i] == 0.0f);
        }
        const auto maps = io::encode_texture_set(set, false);
        int w = 0, h = 0;
        const auto normal = io::decode_png_rgb8(find_map(maps, "NormalGL").bytes, w, h);
        for (std::size_t i = 0; i < normal.size(); i += 3) {
            CHECK(normal[i] == 128);
            CHECK(normal[i + 1] == 128);
            CHECK(normal[i + 2] == 255);
        }
        // Displacement: full scale is the tallest point, so a flat layer is white.
        const GrayImage disp = io::decode_png_gray16(find_map(maps, "Displacement").bytes);
        for (float v : disp.pixels)
            CHECK(v == doctest::Approx(1.0).epsilon(1e-4));
    }

    TEST_CASE("bake: a layer thickening along v gives its analytic normal and GL and DX differ only in green") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        test::LayerSpec spec;
        spec.size = Vec2(0.2, 0.2);
        spec.elements = 400;
        spec.thickness = 0.01;
        spec.thickness_end = 0.05; // slope 0.04 m over 0.2 m along v
        const auto pieces = post::build_pieces(intact_pattern(spec), post::PostOptions{});
        const render::TextureSet set = render::bake(pieces, small(64), *gl);
        const Vec3 expected = Vec3(0.0, -0.04 / 0.2, 1.0).normalized();
        // Away from the seam at v = 0 / 1, where the thickness jumps back.
        int checked = 0;
        for (int y = 16; y < 48; ++y)
            for (int x = 0; x < 64; ++x) {
                const std::size_t i = static_cast<std::size_t>(y * 64 + x);
                const Vec3 n(set.normal[3 * i], set.normal[3 * i + 1], set.normal[3 * i + 2]);
                REQUIRE(std::acos(std::clamp(n.dot(expected), -1.0, 1.0)) * RAD_TO_DEG < 1.0);
                ++checked;
            }
        CHECK(checked > 2000);
        // Heights follow the gradient: row 0 is the top of the image (v near 1, thick).
        CHECK(set.height[static_cast<std::size_t>(10 * 64)] > set.height[static_cast<std::size_t>(50 * 64)]);

        const auto maps = io::encode_texture_set(set, false);
        int w = 0, h = 0;
        const auto gl_map = io::decode_png_rgb8(find_map(maps, "NormalGL").bytes, w, h);
        const auto dx_map = io::decode_png_rgb8(find_map(maps, "NormalDX").bytes, w, h);
        REQUIRE(gl_map.size() == dx_map.size());
        for (std::size_t i = 0; i < gl_map.size(); i += 3) {
            REQUIRE(gl_map[i] == dx_map[i]);
            REQUIRE(gl_map[i + 2] == dx_map[i + 2]);
            REQUIRE(int(gl_map[i + 1]) + int(dx_map[i + 1]) == 255);
        }
        // The slope points down v, so the GL normal's green is below the flat 128.
        const std::size_t mid = 3 * static_cast<std::size_t>(32 * 64 + 32);
        CHECK(gl_map[mid + 1] < 120);
    }

    TEST_CASE("bake: maps tile seamlessly across both borders") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        const auto pattern = test::cracked_plate(800, 1);
        REQUIRE(pattern.num_fragments > 10);
        post::PostOptions po;
        po.shrink_top = 0.05;
        const render::TextureSet set = render::bake(post::build_pieces(pattern, po), small(128), *gl);
        const int n = set.width;
        REQUIRE(set.height_px == n);
        auto at = [&](const std::vector<float>& img, int x, int y) {
            return double(img[static_cast<std::size_t>(((y % n + n) % n) * n + (x % n + n) % n)]);
        };
        for (const auto& [name, img] : {std::pair{"height", &set.height}, {"ao", &set.ao}, {"mask", &set.mask}}) {
            CAPTURE(std::string(name));
            // The pair of lines across each border must look like any pair of neighbouring lines
            // inside the map: no larger than the largest interior pair (a binary crack mask
            // changes by whole pixels where a crack runs along the lines). As a control that the
            // test can fail, lines half a map apart differ far more than neighbours.
            auto line_difference = [&](bool columns, int a, int b) {
                double sum = 0;
                for (int k = 0; k < n; ++k)
                    sum +=
                        columns ? std::abs(at(*img, a, k) - at(*img, b, k)) : std::abs(at(*img, k, a) - at(*img, k, b));
                return sum / n;
            };
            for (bool columns : {true, false}) {
                CAPTURE(columns);
                double largest = 0, mean = 0;
                for (int a = 0; a + 1 < n; ++a) {
                    const double d = line_difference(columns, a, a + 1);
                    largest = std::max(largest, d);
                    mean += d / (n - 1);
                }
                const double border = line_difference(columns, n - 1, 0);
                const double unrelated = line_difference(columns, 0, n / 2);
                CAPTURE(mean);
                CAPTURE(largest);
                CHECK(border <= largest + 1e-9);
                CHECK(border <= 3.0 * mean + 1e-9);
                CHECK(unrelated > 2.5 * mean);
            }
        }
    }

    TEST_CASE("bake: cracks are dark and low and rough and masked while pieces get their own IDs") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        const auto pattern = test::cracked_plate(600, 2);
        const render::TextureSet set = render::bake(post::build_pieces(pattern, post::PostOptions{}), small(96), *gl);
        double crack_lum = 0, top_lum = 0, crack_h = 0, top_h = 0, crack_r = 0, top_r = 0, crack_ao = 0, top_ao = 0;
        int nc = 0, nt = 0;
        std::vector<std::uint32_t> ids;
        for (std::size_t i = 0; i < set.height.size(); ++i) {
            const double lum = set.color[3 * i] + set.color[3 * i + 1] + set.color[3 * i + 2];
            if (set.mask[i] > 0.99f) {
                crack_lum += lum, crack_h += set.height[i], crack_r += set.roughness[i], crack_ao += set.ao[i], ++nc;
            } else if (set.mask[i] < 0.01f) {
                top_lum += lum, top_h += set.height[i], top_r += set.roughness[i], top_ao += set.ao[i], ++nt;
                ids.push_back(std::uint32_t(set.id[3 * i]) << 16 | std::uint32_t(set.id[3 * i + 1]) << 8
                              | set.id[3 * i + 2]);
            }
        }
        REQUIRE(nc > 100);
        REQUIRE(nt > 100);
        CHECK(crack_lum / nc < 0.5 * top_lum / nt);
        CHECK(crack_h / nc < 0.2 * top_h / nt);
        CHECK(crack_r / nc > top_r / nt);
        CHECK(crack_ao / nc < top_ao / nt);
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        CHECK(ids.size() > std::size_t(pattern.num_fragments / 2));
    }

    TEST_CASE("bake: a shader that does not compile reports its log with numbered lines") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        try {
            render::GlProgram broken("broken", "void main() { gl_Position = vec4(0.0); }",
                                     "out vec4 o;\nvoid main() {\n  o = vec4(undefined_thing);\n}\n");
            FAIL("expected a compile error");
        } catch (const NumericError& e) {
            const std::string what = e.what();
            CHECK(what.find("failed to compile") != std::string::npos);
            CHECK(what.find("undefined_thing") != std::string::npos);
            CHECK(what.find("   1 | #version 330 core") != std::string::npos);
        }
    }
}
