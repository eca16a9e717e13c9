// The float displacement (EXR) and the 16-bit PNG agree, and neither leaves the documented range
// [0, displacement_scale_m]: with multisampling, a pixel whose centre lies outside a triangle that
// covers some of its samples used to extrapolate the triangle's height to the centre, which along
// steep crack walls gave -16..+20 mm on a 14 mm layer (needles in the EXR, clipped in the PNG).
// Plane, cylinder and sphere; and each preset uses the range (not a plateau with ink lines).
#include "core/json.hpp"
#include "io/png.hpp"
#include "io/texture_set.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

using namespace crackle;
namespace fs = std::filesystem;

TEST_SUITE("render") {
    TEST_CASE("height: the EXR and the 16-bit PNG hold the same heights, within [0, displacement_scale_m], on "
              "plane, cylinder and sphere") {
        if (!test::gl_context_or_skip()) return;
        for (const char* preset : {"mud", "bark", "fruit"}) {
            CAPTURE(std::string(preset));
            const fs::path dir = test::scratch_dir("height-range");
            const auto r =
                test::run_cli({"-q", "bake", preset, "--size", "192", "--set", "simulation.elements=1500", "--set",
                               "bake.exr=true", "--out", dir.string(), "--json", (dir / "r.json").string()});
            REQUIRE(r.code == 0);
            const double scale =
                Json::parse(test::slurp(dir / "r.json"), "r.json").find("displacement_scale_m")->as_number();
            REQUIRE(scale > 0);
            const std::string exr_bytes = test::slurp(dir / (std::string(preset) + "_Displacement.exr"));
            int n = 0;
            const std::vector<float> exr =
                io::decode_exr_gray(std::vector<std::uint8_t>(exr_bytes.begin(), exr_bytes.end()), n);
            const std::string png_bytes = test::slurp(dir / (std::string(preset) + "_Displacement.png"));
            const GrayImage png = io::decode_png_gray16(std::vector<std::uint8_t>(png_bytes.begin(), png_bytes.end()));
            REQUIRE(n == 192);
            REQUIRE(png.pixels.size() == exr.size());
            const auto [lo, hi] = std::minmax_element(exr.begin(), exr.end());
            CHECK(*lo >= -1e-6 * scale);
            CHECK(*hi <= scale * (1 + 1e-5));
            double worst = 0;
            for (std::size_t i = 0; i < exr.size(); ++i)
                worst = std::max(worst, std::abs(double(png.pixels[i]) * scale - double(exr[i])));
            CHECK(worst <= scale / 65535.0 + 1e-9); // the PNG's quantisation, nothing clipped

            // The range is used: cracks reach down, tops reach full scale; bark's furrows cover a
            // good part of the trunk (its median used to sit at 95 % of the range: a plateau).
            std::vector<float> sorted(png.pixels);
            std::sort(sorted.begin(), sorted.end());
            auto quantile = [&](double q) { return double(sorted[static_cast<std::size_t>(q * (sorted.size() - 1))]); };
            CAPTURE(quantile(0.01));
            CAPTURE(quantile(0.5));
            CAPTURE(quantile(0.99));
            CHECK(quantile(0.01) < 0.6); // cracks reach well below the tops (fruit: crack_depth 0.6)
            CHECK(quantile(0.99) > 0.85);
            if (std::string(preset) == "bark") {
                CHECK(quantile(0.5) < 0.75);
                CHECK(quantile(0.25) < 0.5);
            }
        }
    }
}
