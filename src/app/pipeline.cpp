#include "app/pipeline.hpp"

#include "core/log.hpp"
#include "core/timer.hpp"
#include "fracture/fem_split.hpp"
#include "fracture/mass_spring.hpp"

#include <cstdlib>
#include <filesystem>

namespace crackle::app {

namespace {

fracture::MassSpringOptions mass_spring_options(const io::Preset& preset) {
    fracture::MassSpringOptions o;
    o.lattice = preset.text("simulation.lattice") == "regular" ? fracture::Lattice::Regular : fracture::Lattice::Random;
    o.layers = static_cast<int>(preset.integer("simulation.layers"));
    o.anchor_slide = preset.number("simulation.anchor_slide");
    o.break_jitter = preset.number("simulation.break_jitter");
    o.tolerance = preset.number("simulation.solver_tolerance");
    o.max_newton_iterations =
        static_cast<int>(std::min<std::int64_t>(preset.integer("simulation.solver_max_iterations"), 1000));
    return o;
}

void run_mass_spring_method(const io::Preset& preset, SimulationResult& r, StepTimes& times) {
    Timer step;
    const fracture::MassSpringOptions o = mass_spring_options(preset);
    // One mass per Voronoi cell; a cell covers two triangles of a mesh with `elements` of them,
    // so a preset meshes the surface at the same resolution whatever its method.
    const std::size_t masses = std::max<std::size_t>(16, r.scene->discretize.elements / 2);
    Rng sampling(r.scene->seed, RngStream::Sampling);
    const mesh::SurfaceMesh lattice =
        fracture::mass_spring_mesh(r.scene->surface, masses, o.lattice, r.scene->discretize.sampling, sampling);
    times.emplace_back("lattice", step.seconds());

    step.reset();
    Rng rng(r.scene->seed, RngStream::Fracture);
    fracture::MassSpringModel model(lattice, r.scene->surface, r.scene->growth, r.scene->shrinkage,
                                    layer_fields(*r.scene), o, rng);
    times.emplace_back("assembly", step.seconds());
    step.reset();
    fracture::MassSpringStats ms;
    r.pattern = fracture::run_mass_spring(model, fracture_options(preset), rng, &r.run, &ms);
    times.emplace_back("fracture", step.seconds());
    times.emplace_back("fracture.solve", r.run.solve_seconds);
    times.emplace_back("fracture.stress", r.run.stress_seconds);
    std::size_t intact = 0;
    for (const auto& s : model.springs())
        intact += !s.broken;
    r.elements_initial = model.springs().size();
    r.elements_final = intact;
    r.nodes = model.num_vertices() * static_cast<std::size_t>(model.layers());
    r.crack_depth_layers = ms.crack_depth_layers;
    r.newton_iterations = ms.newton_iterations;
    r.anchor_slides = ms.slides;
    r.factorizations = ms.factorizations;
}

} // namespace

SimulationResult run_simulation(const io::Preset& preset, StepTimes& times) {
    SimulationResult r;
    Timer step;
    r.scene = make_scene(preset);
    times.emplace_back("preset", step.seconds());
    if (preset.text("simulation.method") == "mass-spring") {
        run_mass_spring_method(preset, r, times);
    } else {
        mesh::SurfaceMesh surface_mesh = discretize_scene(*r.scene, &times);
        r.elements_initial = surface_mesh.num_faces();
        const bool removal = preset.text("simulation.method") == "fem-remove";
        if (removal) {
            // Element removal takes out whole elements: on elements much wider than the layer is
            // thick, most of the layer goes (thesis Fig. 5.11, failure mode F6).
            const double edge = mesh::mesh_quality(surface_mesh).edge_mean;
            const double h = 0.5 * (r.scene->thickness.min_value() + r.scene->thickness.max_value());
            if (edge > 1.5 * h && preset.number("simulation.min_element_size") == 0.0)
                log::warn("elements (", edge * 100, " cm) are much wider than the layer is thick (", h * 100,
                          " cm): element removal will take out most of the layer; raise simulation.elements or set "
                          "simulation.min_element_size");
        }
        step.reset();
        sim::FemModel model(std::move(surface_mesh), r.scene->surface, r.scene->growth, r.scene->shrinkage,
                            layer_fields(*r.scene), fem_options(preset));
        times.emplace_back("assembly", step.seconds());
        step.reset();
        Rng rng(r.scene->seed, RngStream::Fracture);
        if (removal) {
            r.pattern = fracture::run_fem_remove(model, fracture_options(preset), rng, &r.run);
        } else {
            fracture::SplitOptions split;
            split.min_angle_deg = preset.number("simulation.min_angle");
            split.exclusion_radius = preset.number("simulation.exclusion_radius");
            split.griffith = preset.flag("simulation.griffith");
            split.smoothing_radius = preset.number("simulation.smoothing_radius");
            split.vm_threshold = preset.number("simulation.vm_threshold");
            split.tip_submodel_levels = static_cast<int>(preset.integer("simulation.tip_submodel"));
            // Debugging aid: check the mesh invariants after every topology change (slow).
            const char* check = std::getenv("CRACKLE_CHECK_INVARIANTS");
            split.check_invariants = check && std::string(check) == "1";
            r.pattern = fracture::run_fem_split(model, fracture_options(preset), split, rng, &r.run);
        }
        times.emplace_back("fracture", step.seconds());
        times.emplace_back("fracture.solve", r.run.solve_seconds);
        times.emplace_back("fracture.stress", r.run.stress_seconds);
        times.emplace_back("fracture.topology", r.run.topology_seconds);
        r.elements_final = model.num_alive();
        r.nodes = 2 * model.mesh().num_vertices();
    }
    step.reset();
    r.statistics = fracture::pattern_statistics(r.pattern);
    times.emplace_back("statistics", step.seconds());
    return r;
}

post::PostOptions post_options(const io::Preset& preset) {
    post::PostOptions o;
    o.curl = preset.number("post.curl");
    o.curl_width = preset.number("post.curl_width");
    const auto& s = preset.numbers("post.shrinkage");
    o.shrink_top = s[0];
    o.shrink_bottom = s[1];
    o.bevel = preset.number("post.bevel");
    return o;
}

namespace {
/// sRGB → linear (the shaders work in linear light; the colour target encodes back).
Vec3 linear_from_srgb(const std::vector<double>& c) {
    auto f = [](double x) { return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4); };
    return Vec3(f(c[0]), f(c[1]), f(c[2]));
}
} // namespace

render::BakeOptions bake_options(const io::Preset& preset) {
    render::BakeOptions o;
    o.size = static_cast<int>(preset.integer("bake.size"));
    o.samples = static_cast<int>(preset.integer("bake.samples"));
    o.color = linear_from_srgb(preset.numbers("bake.color"));
    o.crack_color = linear_from_srgb(preset.numbers("bake.crack_color"));
    o.color_variation = preset.number("bake.color_variation");
    o.grain = preset.number("bake.grain");
    o.grain_size = preset.number("bake.grain_size");
    o.grain_stretch = preset.number("bake.grain_stretch");
    o.roughness = preset.number("bake.roughness");
    o.roughness_variation = preset.number("bake.roughness_variation");
    o.ao_radius = preset.number("bake.ao_radius");
    o.ao_strength = preset.number("bake.ao_strength");
    o.seed = static_cast<std::uint32_t>(preset.integer("simulation.seed") & 0xffffffff);
    return o;
}

std::string output_name(const io::Preset& preset) {
    const std::string& configured = preset.text("bake.name");
    if (!configured.empty()) return configured;
    std::string name = preset.name;
    if (name.size() > 5 && name.substr(name.size() - 5) == ".toml") name = std::filesystem::path(name).stem().string();
    for (char& c : name)
        if (c == '/' || c == '\\') c = '-';
    return name;
}

} // namespace crackle::app
