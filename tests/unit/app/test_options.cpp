// Typed options and the schema agree: options mapped from a preset that sets nothing equal the
// structs' own defaults, so code that builds an options struct by hand (tests, the bench) runs
// what a preset would.
#include "app/run/options.hpp"
#include "app/run/run_plan.hpp"
#include "fracture/fem_split/fem_split.hpp"
#include "fracture/graph_fem/graph_fem.hpp"
#include "fracture/mass_spring/mass_spring.hpp"
#include "fracture/method.hpp"
#include "io/preset.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace crackle;

namespace {

/// A preset that sets no key: every value is the schema's default.
io::Preset defaults() {
    const char* dir = std::getenv("CRACKLE_TEST_OUTPUT");
    const std::filesystem::path folder = std::filesystem::path(dir ? dir : "/tmp") / "options";
    std::filesystem::create_directories(folder);
    const std::filesystem::path file = folder / "defaults.toml";
    std::ofstream(file) << "# sets nothing\n";
    io::PresetRequest r;
    r.name_or_path = file.string();
    return io::load_preset(r);
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("options: every options struct's defaults are the schema's") {
        // Whole structs compared (their defaulted operator== takes every field, so a new field
        // cannot slip by); the few fields a preset does not set from its own key are named.
        const io::Preset p = defaults();
        CHECK(app::fracture_options(p) == fracture::FractureOptions{});
        CHECK(app::fem_options(p) == sim::FemOptions{});
        CHECK(app::surface_options(p) == mesh::SurfaceOptions{});
        CHECK(app::growth_options(p) == sim::GrowthOptions{});
        CHECK(app::post_options(p) == post::PostOptions{});

        const post::PieceMesh square; // a square tile: bake.size is both sides
        render::BakeOptions bake = app::bake_options(p, square);
        const render::BakeOptions bake_default;
        // sRGB in the schema, linear in the struct: the struct keeps six digits of the conversion.
        CHECK((bake.shading.color - bake_default.shading.color).norm() < 1e-6);
        CHECK((bake.shading.crack_color - bake_default.shading.crack_color).norm() < 1e-6);
        bake.shading.color = bake_default.shading.color;
        bake.shading.crack_color = bake_default.shading.crack_color;
        CHECK(bake == bake_default);

        // The methods' own options (mapped in their folders).
        fracture::SplitOptions split = fracture::split_options(p);
        // material.initiation_length = "auto" is the layer's thickness; the struct's 0 = a node's own
        // stress, what hand-built tests of the split loop start from.
        CHECK(p.is_auto("material.initiation_length"));
        CHECK(split.initiation_fraction == 1.0);
        split.initiation_fraction = 0.0;
        CHECK(split == fracture::SplitOptions{});
        CHECK(fracture::mass_spring_options(p) == fracture::MassSpringOptions{});
        CHECK(fracture::graph_fem_options(p) == fracture::GraphFemOptions{});

        // The run plan holds each stage's options as mapped here, once.
        const app::RunPlan plan = app::make_run_plan(p);
        CHECK(plan.surface == app::surface_options(p));
        CHECK(plan.growth == app::growth_options(p));
        CHECK(plan.fracture == app::fracture_options(p));
        CHECK(plan.fem == app::fem_options(p));
        CHECK(plan.post == app::post_options(p));
        CHECK(plan.bake == app::bake_options(p));
        CHECK(plan.map.width == plan.bake.width);
        CHECK(plan.map.height == plan.bake.height);
    }

    TEST_CASE("options: every method's keys are in the schema, under the method, and every method can be made") {
        const io::Preset p = defaults();
        for (const fracture::MethodInfo& m : fracture::methods()) {
            CAPTURE(m.name);
            for (const KeySpec& k : m.keys) {
                CAPTURE(k.name());
                const KeySpec* spec = io::find_key(k.name());
                REQUIRE(spec != nullptr);
                CHECK(spec->group == m.name);
            }
            CHECK(bool(m.make));
        }
        const KeySpec* method = io::find_key("simulation.method");
        REQUIRE(method != nullptr);
        CHECK(method->choices == fracture::method_names());
        CHECK(fracture::make_method(p) != nullptr); // the default method
    }
}
