// Typed options and the schema agree: options mapped from a preset that sets nothing equal the
// structs' own defaults, so code that builds an options struct by hand (tests, the bench) runs
// what a preset would.
#include "app/options.hpp"
#include "fracture/fem_split/fem_split.hpp"
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
        const io::Preset p = defaults();

        const fracture::FractureOptions fracture = app::fracture_options(p);
        CHECK(fracture == fracture::FractureOptions{});

        const sim::FemOptions fem = app::fem_options(p), fem_default;
        CHECK(fem.solver == fem_default.solver);
        CHECK(fem.tolerance == fem_default.tolerance);
        CHECK(fem.max_iterations == fem_default.max_iterations);
        CHECK(fem.stiffness_refresh == fem_default.stiffness_refresh);

        const mesh::SurfaceOptions surface = app::surface_options(p), surface_default;
        CHECK(surface.kind == surface_default.kind);
        CHECK(surface.size == surface_default.size);

        const sim::GrowthOptions growth = app::growth_options(p), growth_default;
        CHECK(growth.kind == growth_default.kind);
        CHECK(growth.r1 == growth_default.r1);
        CHECK(growth.r2 == growth_default.r2);
        CHECK(growth.angle_deg == growth_default.angle_deg);

        const post::PostOptions post = app::post_options(p), post_default;
        CHECK(post.curl == post_default.curl);
        CHECK(post.curl_width == post_default.curl_width);
        CHECK(post.shrink_top == post_default.shrink_top);
        CHECK(post.shrink_bottom == post_default.shrink_bottom);
        CHECK(post.bevel == post_default.bevel);

        const post::PieceMesh square; // a square tile: bake.size is both sides
        const render::BakeOptions bake = app::bake_options(p, square), bake_default;
        CHECK(bake.width == bake_default.width);
        CHECK(bake.height == bake_default.height);
        CHECK(bake.samples == bake_default.samples);
        const render::ShadingOptions &s = bake.shading, &s0 = bake_default.shading;
        CHECK((s.color - s0.color).norm() < 1e-4); // sRGB in the schema, linear here
        CHECK((s.crack_color - s0.crack_color).norm() < 1e-4);
        CHECK(s.color_variation == s0.color_variation);
        CHECK(s.grain == s0.grain);
        CHECK(s.grain_size == s0.grain_size);
        CHECK(s.grain_stretch == s0.grain_stretch);
        CHECK(s.roughness == s0.roughness);
        CHECK(s.roughness_variation == s0.roughness_variation);
        CHECK(s.cavity == s0.cavity);
        const render::ReliefOptions &r = bake.relief, &r0 = bake_default.relief;
        CHECK(r.crack_width == r0.crack_width);
        CHECK(r.crack_depth == r0.crack_depth);
        CHECK(r.crack_shape == r0.crack_shape);
        for (const auto& [layer, layer0] : {std::pair{r.fibre, r0.fibre}, {r.flake, r0.flake}, {r.grit, r0.grit}}) {
            CHECK(layer.depth == layer0.depth);
            CHECK(layer.size == layer0.size);
            CHECK(layer.stretch == layer0.stretch);
        }
        CHECK(bake.crack_age == bake_default.crack_age);
        CHECK(bake.ao_radius == bake_default.ao_radius);
        CHECK(bake.ao_strength == bake_default.ao_strength);
        CHECK(bake.seed == bake_default.seed);

        // The methods' own options (mapped in their folders).
        const fracture::SplitOptions split = fracture::split_options(p), split_default;
        CHECK(split.snap_fraction == split_default.snap_fraction);
        CHECK(split.min_angle_deg == split_default.min_angle_deg);
        CHECK(split.exclusion_radius == split_default.exclusion_radius);
        CHECK(split.griffith == split_default.griffith);
        CHECK(split.smoothing_radius == split_default.smoothing_radius);
        CHECK(split.vm_threshold == split_default.vm_threshold);
        CHECK(split.tip_submodel_levels == split_default.tip_submodel_levels);
        CHECK(split.check_invariants == split_default.check_invariants);

        const fracture::MassSpringOptions springs = fracture::mass_spring_options(p), springs_default;
        CHECK(springs.lattice == springs_default.lattice);
        CHECK(springs.layers == springs_default.layers);
        CHECK(springs.anchor_slide == springs_default.anchor_slide);
        CHECK(springs.break_jitter == springs_default.break_jitter);
        CHECK(springs.tolerance == springs_default.tolerance);
        CHECK(springs.max_newton_iterations == springs_default.max_newton_iterations);
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
