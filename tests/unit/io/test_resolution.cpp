// simulation.elements = "auto": the rule (crack spacing from the thinnest layer, the texture cap,
// the curved-surface minimum), the preview's coarser rule, and how the key reads and refuses.
#include "core/error.hpp"
#include "io/preset.hpp"
#include "io/resolution.hpp"
#include "support/presets.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace crackle;

namespace {

using test::load;
using test::load_error;

} // namespace

TEST_SUITE("io") {
    TEST_CASE("resolution: auto follows the area over the thinnest thickness squared, a given number is kept") {
        const io::Preset mud = load("mud", {"simulation.elements=auto", "bake.size=2048"});
        const double q = mud.number("simulation.elements_per_h2");
        const io::ElementCount c = io::element_count(mud);
        CHECK(c.automatic);
        CHECK(c.elements == std::llround(q * 0.25 / (0.01 * 0.01)));
        CHECK(c.reason.find("h = 0.01 m") != std::string::npos);
        // Twice the thickness: a quarter of the elements; twice the tile side: four times.
        CHECK(io::element_count(load("mud", {"simulation.elements=auto", "material.thickness=[0.02,0.02]"})).elements
              == std::llround(q * 0.25 / (0.02 * 0.02)));
        CHECK(io::element_count(load("mud", {"simulation.elements=auto", "surface.size=[1.0,1.0]"})).elements
              == std::llround(q * 1.0 / (0.01 * 0.01)));
        // The thinner of top and bottom, lowered by a thickness variation.
        const io::Preset varied =
            load("mud", {"simulation.elements=auto", "material.thickness=[0.02,0.03]",
                         "variation.thickness.pattern=gradient", "variation.thickness.amplitude=0.5"});
        CHECK(io::element_count(varied).elements == std::llround(q * 0.25 / (0.01 * 0.01)));
        // A mesh that follows the thickness (1 → 4 cm): the area integral of 1/h², 1/(t₀·t₁) on the ramp.
        CHECK(io::element_count(load("mud/thickness-gradient", {"simulation.elements=auto"})).elements
              == std::llround(q * 0.25 / (0.01 * 0.04)));
        // The density is the preset's: 2 per h² by default, 4 for mud's T-junctions, 8 for bark's
        // crack density, 16 for the Siberian elm's T share, 16 for the Table 5.2 family (rows h, m, n
        // 13-17 % off at 4), 4 for the fruit's T share (and the glaze's, inherited), 8 for the
        // thicker isogonic sphere's (and z-elongated's); the reason names it.
        CHECK(q == 4.0);
        CHECK(load("bark").number("simulation.elements_per_h2") == 8.0);
        CHECK(load("bark/siberian-elm").number("simulation.elements_per_h2") == 16.0);
        CHECK(load("bark/table-5-2-base").number("simulation.elements_per_h2") == 16.0);
        CHECK(load("bark/table-5-2-h").number("simulation.elements_per_h2") == 16.0);
        CHECK(load("fruit").number("simulation.elements_per_h2") == 4.0);
        CHECK(load("sphere/crackle-glaze").number("simulation.elements_per_h2") == 4.0);
        CHECK(load("sphere/isogonic").number("simulation.elements_per_h2") == 8.0);
        CHECK(load("sphere/z-elongated").number("simulation.elements_per_h2") == 8.0);
        CHECK(c.reason.find("4 elements per h²") != std::string::npos);
        CHECK(io::element_count(load("mud", {"simulation.elements=auto", "simulation.elements_per_h2=1"})).elements
              == std::llround(1.0 * 0.25 / (0.01 * 0.01)));
        CHECK(load_error("mud", {"simulation.elements_per_h2=0"}).find("simulation.elements_per_h2")
              != std::string::npos);
        // A number is a number.
        const io::ElementCount fixed = io::element_count(load("mud", {"simulation.elements=1234"}));
        CHECK(!fixed.automatic);
        CHECK(fixed.elements == 1234);
    }

    TEST_CASE("resolution: the texture caps auto, a curved surface's minimum floors it, the preview is coarser") {
        const double per_pixel = io::resolution_rule().pixels_per_element;
        // A 2 mm layer over a 1 m tile wants 800k elements; a 256 px texture shows 8192.
        const io::Preset fine = load("mud", {"simulation.elements=auto", "material.thickness=[0.002,0.002]",
                                             "surface.size=[1.0,1.0]", "bake.size=256"});
        const io::ElementCount capped = io::element_count(fine);
        CHECK(capped.elements == std::llround(256.0 * 256.0 / per_pixel));
        CHECK(capped.reason.find("capped") != std::string::npos);
        // A thick layer on a long trunk: the rule would give a few hundred, the cylinder needs more.
        const io::Preset trunk =
            load("bark", {"simulation.elements=auto", "material.thickness=[0.2,0.2]", "surface.size=[0.5,50]"});
        CHECK(io::element_count(trunk).elements == io::minimum_elements(trunk));
        CHECK(io::minimum_elements(trunk) > 8000);
        CHECK(io::minimum_elements(load("mud")) == 0);
        // The preview: the coarser rule, also applied to an explicit count that is finer.
        const io::Preset mud = load("mud", {"simulation.elements=auto"});
        const io::ElementCount preview = io::element_count(mud, true);
        CHECK(preview.automatic);
        CHECK(preview.elements < io::element_count(mud).elements);
        CHECK(io::element_count(load("mud", {"simulation.elements=50000"}), true).elements == preview.elements);
        CHECK(io::element_count(load("mud", {"simulation.elements=500"}), true).elements == 500);
    }

    TEST_CASE("resolution: one rule gives the maps' pixels, and the texture cap counts those pixels") {
        // bake.size is the longer side; the other follows the tile in metres, unless size_v gives it.
        auto map = [](const std::string& preset, std::vector<std::string> overrides) {
            const io::MapSize m = io::map_size(load(preset, overrides));
            return std::pair{m.width, m.height};
        };
        CHECK(map("mud", {"bake.size=512"}) == std::pair{512, 512});
        CHECK(map("fruit", {"bake.size=512"}) == std::pair{512, 256}); // the sphere's tile is 2πR × πR
        CHECK(map("mud", {"bake.size=512", "surface.size=[0.5,1.0]"}) == std::pair{256, 512});
        CHECK(map("mud", {"bake.size=512", "surface.size=[0.75,0.25]"}) == std::pair{512, 171});
        CHECK(map("fruit", {"bake.size=512", "bake.size_v=300"}) == std::pair{512, 300});
        // The cap is one element per 8 of those pixels: a 2:1 map holds half a square's elements
        // (until 2026-12-07 the cap read bake.size² and ignored the map's shape and size_v).
        const double per_pixel = io::resolution_rule().pixels_per_element;
        const io::Preset sphere = load("fruit", {"simulation.elements=auto", "bake.size=256"});
        const io::ElementCount capped = io::element_count(sphere);
        CHECK(capped.elements == std::llround(256.0 * 128.0 / per_pixel));
        CHECK(capped.reason.find("capped at 4096 for a 256x128 px texture") != std::string::npos);
        const io::Preset rows = load("mud", {"simulation.elements=auto", "material.thickness=[0.002,0.002]",
                                             "surface.size=[1.0,1.0]", "bake.size=256", "bake.size_v=64"});
        CHECK(io::element_count(rows).elements == std::llround(256.0 * 64.0 / per_pixel));
    }
    TEST_CASE("resolution: simulation.elements reads auto in TOML and --set, and refuses other words") {
        CHECK(load("mud", {"simulation.elements=auto"}).is_auto("simulation.elements"));
        CHECK(load("mud", {"simulation.elements=\"auto\""}).is_auto("simulation.elements"));
        CHECK(!load("mud", {"simulation.elements=900"}).is_auto("simulation.elements"));
        const std::string word = load_error("mud", {"simulation.elements=automatic"});
        CHECK(word.find("simulation.elements") != std::string::npos);
        CHECK(word.find("\"auto\" or a whole number") != std::string::npos);
        const std::string quoted = load_error("mud", {"simulation.elements=\"many\""});
        CHECK(quoted.find("not \"many\"") != std::string::npos);
        CHECK(load_error("mud", {"simulation.elements=10"}).find("[32, 2000000]") != std::string::npos);
        // A curved surface with too few elements is still refused, and pointed to auto.
        CHECK(load_error("bark", {"simulation.elements=50"}).find("or \"auto\"") != std::string::npos);
    }
}
