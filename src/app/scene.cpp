#include "app/scene.hpp"

#include "core/error.hpp"
#include "io/png.hpp"

namespace crackle::app {

mesh::SurfaceOptions surface_options(const io::Preset& preset) {
    mesh::SurfaceOptions o;
    const std::string kind = preset.text("surface.kind");
    o.kind = kind == "plane"    ? mesh::SurfaceKind::Plane
             : kind == "sphere" ? mesh::SurfaceKind::Sphere
                                : mesh::SurfaceKind::Cylinder;
    const auto& size = preset.numbers("surface.size");
    o.size = Vec2(size[0], size.size() > 1 ? size[1] : size[0]);
    return o;
}

sim::GrowthOptions growth_options(const io::Preset& preset) {
    sim::GrowthOptions o;
    const std::string kind = preset.text("growth.kind");
    o.kind = kind == "none"       ? sim::GrowthKind::None
             : kind == "isogonic" ? sim::GrowthKind::Isogonic
                                  : sim::GrowthKind::Anisotropic;
    const auto& rate = preset.numbers("growth.rate");
    o.r1 = rate[0];
    o.r2 = rate[1];
    o.angle_deg = preset.number("growth.angle_deg");
    return o;
}

sim::VariationOptions variation_options(const io::Preset& preset, const std::string& property) {
    const std::string sec = "variation." + property + ".";
    sim::VariationOptions o;
    const std::string pattern = preset.text(sec + "pattern");
    o.pattern = pattern == "gradient" ? sim::PatternKind::Gradient
                : pattern == "noise"  ? sim::PatternKind::Noise
                : pattern == "image"  ? sim::PatternKind::Image
                                      : sim::PatternKind::None;
    o.amplitude = preset.number(sec + "amplitude");
    o.scale = preset.number(sec + "scale");
    o.octaves = static_cast<int>(preset.integer(sec + "octaves"));
    o.angle_deg = preset.number(sec + "angle_deg");
    if (o.pattern == sim::PatternKind::Image) {
        try {
            o.image = std::make_shared<GrayImage>(io::read_png_gray(preset.path(sec + "image")));
        } catch (const InputError& e) {
            throw InputError(preset.entry(sec + "image").source.text() + ": " + e.what());
        }
    }
    return o;
}

std::unique_ptr<Scene> make_scene(const io::Preset& preset) {
    const mesh::Surface surface(surface_options(preset));
    const auto seed = static_cast<std::uint64_t>(preset.integer("simulation.seed"));
    const auto& thickness = preset.numbers("material.thickness");
    const auto& shrink = preset.numbers("material.shrinkage");
    // Each property's noise has its own stream, so editing one pattern leaves the others alone.
    auto scene = std::unique_ptr<Scene>(new Scene{
        surface,
        sim::GrowthField(growth_options(preset), surface.kind()),
        sim::ShrinkageOptions{shrink[0], shrink[1]},
        sim::PropertyField(thickness[0], thickness[1], variation_options(preset, "thickness"), surface, seed, 1),
        sim::PropertyField(preset.number("material.young_modulus"), variation_options(preset, "young_modulus"), surface,
                           seed, 2),
        sim::PropertyField(preset.number("material.threshold_stress"), variation_options(preset, "threshold_stress"),
                           surface, seed, 3),
        sim::PropertyField(preset.number("material.toughness"), variation_options(preset, "toughness"), surface, seed,
                           4),
        preset.number("material.poisson_ratio"),
        mesh::DiscretizeOptions{},
        preset.text("simulation.density") == "thickness",
        seed,
    });
    scene->discretize.elements = static_cast<std::size_t>(preset.integer("simulation.elements"));
    scene->discretize.sampling.jitter = preset.number("simulation.jitter");
    scene->discretize.sampling.max_iterations = static_cast<int>(preset.integer("simulation.repulsion_iterations"));
    return scene;
}

mesh::SurfaceMesh discretize_scene(const Scene& scene, StepTimes* times) {
    Rng rng(scene.seed, RngStream::Sampling);
    mesh::SpacingOverUv spacing;
    if (scene.density_follows_thickness) {
        // Element size ∝ local thickness: crack spacing scales with thickness (Fig. 5.29).
        const double reference = scene.thickness.max_value();
        spacing = [&scene, reference](const Vec2& uv) {
            Vec3 p = Vec3::Zero();
            if (scene.surface.kind() == mesh::SurfaceKind::Sphere) {
                const double lon = TWO_PI * uv.x(), colat = PI * (1.0 - uv.y());
                p = scene.surface.radius()
                    * Vec3(std::sin(colat) * std::cos(lon), std::sin(colat) * std::sin(lon), std::cos(colat));
            } else {
                p = scene.surface.position(
                    Vec2(uv.x() * scene.surface.period().x(), uv.y() * scene.surface.period().y()));
            }
            return scene.thickness.at(p, uv) / reference;
        };
    }
    return mesh::discretize(scene.surface, scene.discretize, spacing, rng, times);
}

sim::FemOptions fem_options(const io::Preset& preset) {
    sim::FemOptions o;
    o.solver = preset.text("simulation.solver") == "direct" ? sim::SolverKind::Direct : sim::SolverKind::Cg;
    o.tolerance = preset.number("simulation.solver_tolerance");
    o.max_iterations = static_cast<int>(preset.integer("simulation.solver_max_iterations"));
    return o;
}

fracture::FractureOptions fracture_options(const io::Preset& preset) {
    fracture::FractureOptions o;
    o.duration = preset.number("simulation.duration");
    o.min_element_size = preset.number("simulation.min_element_size");
    o.max_events = static_cast<std::size_t>(preset.integer("simulation.max_events"));
    o.local_relaxation = preset.text("simulation.relaxation") == "local";
    o.local_tolerance = preset.number("simulation.local_tolerance");
    o.drift_tolerance = preset.number("simulation.drift_tolerance");
    return o;
}

sim::LayerFields layer_fields(const Scene& scene) {
    return {&scene.thickness, &scene.young_modulus, &scene.threshold_stress, &scene.toughness, scene.poisson_ratio};
}

void require_available_method(const io::Preset& preset) {
    const std::string method = preset.text("simulation.method");
    if (method == "fem-remove" || method == "fem-split" || method == "mass-spring") return;
    throw InputError(preset.entry("simulation.method").source.text(),
                     "simulation.method = \"" + method + "\" is not available in this version",
                     "use \"fem-split\", \"fem-remove\" or \"mass-spring\"");
}

} // namespace crackle::app
