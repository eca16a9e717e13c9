#include "app/run/scene.hpp"

#include "core/log.hpp"

#include <cstdio>

namespace crackle::app {

std::unique_ptr<Scene> make_scene(const RunPlan& plan) {
    const mesh::Surface surface(plan.surface);
    const std::uint64_t seed = plan.seed;
    const LayerPlan& l = plan.layer;
    // Each property's noise has its own stream, so editing one pattern leaves the others alone.
    auto scene = std::unique_ptr<Scene>(new Scene{
        surface,
        sim::GrowthField(plan.growth, surface.kind()),
        l.shrinkage,
        sim::PropertyField(l.thickness_min, l.thickness_max, l.thickness, surface, seed, 1),
        sim::PropertyField(l.young_modulus, l.young, surface, seed, 2),
        sim::PropertyField(l.threshold_stress, l.threshold, surface, seed, 3),
        sim::PropertyField(l.toughness, l.toughness_variation, surface, seed, 4),
        l.poisson_ratio,
        mesh::DiscretizeOptions{},
        l.density_follows_thickness,
        seed,
    });
    scene->discretize.elements = static_cast<std::size_t>(plan.elements.elements);
    scene->discretize.sampling.jitter = l.jitter;
    scene->discretize.sampling.max_iterations = l.repulsion_iterations;
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
    mesh::SurfaceMesh m = mesh::discretize(scene.surface, scene.discretize, spacing, rng, times);
    // Stability envelope (docs/benchmarks.md): on poorly shaped starting meshes (uniformly random
    // points, no repulsion) fem-remove's crack density rose 22 % and graph-fem lost a third of its
    // fragments, silently. Say so with the figure.
    const mesh::MeshQuality q = mesh::mesh_quality(m);
    if (q.fraction_below_10deg > 0.01) {
        char figure[96];
        std::snprintf(figure, sizeof figure, "%.1f %% of its triangles below 10 degrees (the worst %.1f)",
                      100.0 * q.fraction_below_10deg, q.min_angle_deg);
        log::warn("the starting mesh has ", figure,
                  "; crack patterns then depend on the mesh (fem-remove's crack density, graph-fem's junctions): "
                  "raise simulation.repulsion_iterations (default 100) or lower simulation.jitter");
    }
    return m;
}

sim::LayerFields layer_fields(const Scene& scene) {
    return {&scene.thickness, &scene.young_modulus, &scene.threshold_stress, &scene.toughness, scene.poisson_ratio};
}

} // namespace crackle::app
