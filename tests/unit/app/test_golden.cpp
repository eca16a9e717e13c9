#include "io/png.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"
#include "support/image_compare.hpp"

#include <doctest/doctest.h>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

std::vector<std::uint8_t> bytes_of(const fs::path& p) {
    const std::string s = test::slurp(p);
    return std::vector<std::uint8_t>(s.begin(), s.end());
}

/// Bakes a golden scene and compares three maps with the references (style guide §8):
/// heights within 2/255 of full scale, normals within 2°, albedo within 4/255 per channel,
/// each on at least 99.75 % of the pixels.
void check_golden(const std::string& scene) {
    if (!test::gl_context_or_skip()) return;
    const fs::path source = fs::path(CRACKLE_SOURCE_DIR) / "tests" / "golden";
    const fs::path out = test::scratch_dir("golden-" + scene);
    const auto r = test::run_cli({"-q", "bake", (source / (scene + ".toml")).string(), "--out", out.string()});
    REQUIRE_MESSAGE(r.code == 0, r.err);
    const bool update =
        std::getenv("CRACKLE_UPDATE_GOLDEN") && std::string(std::getenv("CRACKLE_UPDATE_GOLDEN")) == "1";
    for (const std::string map : {"Displacement", "NormalGL", "Color"}) {
        CAPTURE(map);
        const fs::path actual_path = out / (scene + "_" + map + ".png");
        const fs::path ref_path = source / "refs" / (scene + "_" + map + ".png");
        const std::vector<std::uint8_t> actual = bytes_of(actual_path);
        REQUIRE(!actual.empty());
        if (update) {
            fs::copy_file(actual_path, ref_path, fs::copy_options::overwrite_existing);
            MESSAGE("updated " << ref_path.string());
            continue;
        }
        REQUIRE_MESSAGE(fs::exists(ref_path),
                        "missing reference " << ref_path.string() << " (CRACKLE_UPDATE_GOLDEN=1 ctest -L golden)");
        const std::vector<std::uint8_t> reference = bytes_of(ref_path);
        int w = 0, h = 0, rw = 0, rh = 0;
        std::vector<float> errors;
        test::ImageComparison c;
        double tolerance = 0, scale = 1;
        if (map == "Displacement") {
            const GrayImage a = io::decode_png_gray16(actual), b = io::decode_png_gray16(reference);
            REQUIRE(a.pixels.size() == b.pixels.size());
            w = a.width;
            tolerance = 2.0 / 255.0;
            scale = 0.1;
            c = test::compare_pixels(
                a.pixels.size(), tolerance,
                [&](std::size_t i) { return std::abs(double(a.pixels[i]) - double(b.pixels[i])); }, &errors);
        } else {
            const auto a = io::decode_png_rgb8(actual, w, h), b = io::decode_png_rgb8(reference, rw, rh);
            REQUIRE(a.size() == b.size());
            const std::size_t n = a.size() / 3;
            if (map == "NormalGL") {
                tolerance = 2.0; // degrees
                scale = 30.0;
                auto normal = [](const std::vector<std::uint8_t>& v, std::size_t i) {
                    return Vec3(v[3 * i] / 127.5 - 1, v[3 * i + 1] / 127.5 - 1, v[3 * i + 2] / 127.5 - 1).normalized();
                };
                c = test::compare_pixels(
                    n, tolerance,
                    [&](std::size_t i) {
                        return std::acos(std::clamp(normal(a, i).dot(normal(b, i)), -1.0, 1.0)) * RAD_TO_DEG;
                    },
                    &errors);
            } else {
                tolerance = 4.0; // of 255 per channel
                scale = 64.0;
                c = test::compare_pixels(
                    n, tolerance,
                    [&](std::size_t i) {
                        int worst = 0;
                        for (int k = 0; k < 3; ++k)
                            worst = std::max(worst,
                                             std::abs(int(a[3 * i + std::size_t(k)]) - int(b[3 * i + std::size_t(k)])));
                        return double(worst);
                    },
                    &errors);
            }
        }
        if (c.within < 0.9975) {
            const std::string where = test::write_failure(scene + "_" + map, actual, reference, errors, w, scale);
            FAIL(scene << " " << map << " differs from its golden image: " << c.report() << "; see " << where);
        }
        CHECK(c.within >= 0.9975);
    }
}

} // namespace

TEST_SUITE("golden") {
    TEST_CASE("golden: mud on a periodic plane") {
        check_golden("mud_small");
    }
    TEST_CASE("golden: bark on a cylinder") {
        check_golden("bark_small");
    }
    TEST_CASE("golden: a cracked sphere as an equirectangular map") {
        check_golden("fruit_small");
    }
}
