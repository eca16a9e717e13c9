// `crackle bench scale`: the log-log slope it reports, its argument checks, and a quick run end to
// end through the real binary (one CSV row per point, sizes as asked, the chart drawn).
#include "app/bench/bench_scale.hpp"
#include "io/png.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

using namespace crackle;
namespace fs = std::filesystem;

TEST_SUITE("app") {
    TEST_CASE("bench scale: the log-log slope of c·n^k is k, whatever c and the sizes") {
        for (double k : {0.5, 1.0, 1.1, 1.67, 2.0})
            for (double c : {1e-3, 2.5, 40.0}) {
                std::vector<double> n{2500, 5000, 10000, 20000, 31000}, t;
                for (double x : n)
                    t.push_back(c * std::pow(x, k));
                CHECK(app::loglog_slope(n, t) == doctest::Approx(k).epsilon(1e-12));
            }
        // Noise around n^1.5 moves it only a little; one point has no slope.
        CHECK(app::loglog_slope({1e3, 2e3, 4e3, 8e3}, {1.0 * 1.05, 2.828 * 0.97, 8.0 * 1.02, 22.63 * 0.99})
              == doctest::Approx(1.5).epsilon(0.03));
        CHECK(std::isnan(app::loglog_slope({1e3}, {1.0})));
    }

    TEST_CASE("bench scale: refuses a baseline it cannot run, before writing anything") {
        const fs::path out = test::scratch_dir("bench-scale-args");
        const auto r = test::run_cli(
            {"bench", "scale", "--baseline", (out / "no-such-crackle").string(), "--out", (out / "s").string()});
        CHECK(r.code == 2);
        CHECK(r.err.find("scripts/bench-baseline") != std::string::npos);
        CHECK(!fs::exists(out / "s"));
    }

    TEST_CASE("bench scale: the quick run measures both series at the sizes asked, with the mud tile's rule") {
        const fs::path out = test::scratch_dir("bench-scale-quick");
        const std::string cmd = std::string(CRACKLE_BINARY) + " -q bench scale --quick --out '" + out.string() + "' > '"
                                + (out.parent_path() / "bench-scale-quick.log").string() + "' 2>&1";
        REQUIRE(std::system(cmd.c_str()) == 0);
        std::ifstream csv(out / "scale.csv");
        std::string line;
        REQUIRE(std::getline(csv, line));
        CHECK(line.rfind("build,series,elements,tile_m,wall_s", 0) == 0);
        std::map<std::string, int> per_series;
        while (std::getline(csv, line)) {
            CAPTURE(line);
            std::vector<std::string> c;
            std::stringstream s(line);
            for (std::string cell; std::getline(s, cell, ',');)
                c.push_back(cell);
            REQUIRE(c.size() == 12);
            CHECK(c[0] == "this build");
            ++per_series[c[1]];
            const double elements = std::stod(c[2]), tile = std::stod(c[3]);
            // Scale: 2 elements per h² (mud: h = 1 cm); refinement: the preset's 0.5 m tile.
            if (c[1] == "scale")
                CHECK(tile == doctest::Approx(std::sqrt(elements * 1e-4 / 2)).epsilon(1e-5));
            else
                CHECK(tile == doctest::Approx(0.5));
            CHECK(std::stod(c[4]) > 0);             // wall
            CHECK(std::stod(c[5]) > 10);            // peak MiB
            CHECK(std::stod(c[6]) > 10);            // events
            CHECK(std::stod(c[7]) > 1);             // time steps
            CHECK(std::stod(c[8]) > 0.5);           // T share
            CHECK(std::isfinite(std::stod(c[10]))); // rms z against the reference (no floor)
            CHECK((c[11] == "0" || c[11] == "1"));  // within the texture user's tolerance
        }
        CHECK(per_series["scale"] == 2);
        CHECK(per_series["refinement"] == 2);
        const std::string bytes = test::slurp(out / "scale.png");
        REQUIRE(bytes.size() > 1000);
        int w = 0, h = 0;
        const auto rgb = io::decode_png_rgb8(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), w, h);
        CHECK(w >= 1200);
        std::size_t inked = 0;
        for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
            if (rgb[i] < 200 || rgb[i + 1] < 200 || rgb[i + 2] < 200) ++inked;
        CHECK(double(inked) / double(w * h) > 0.01);
    }
}
