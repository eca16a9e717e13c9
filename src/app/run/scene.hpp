#pragma once
/// @file A run plan turned into the pipeline's typed inputs: the surface, its growth field,
/// material shrinkage and property fields, and the discretization options.

#include "app/run/options.hpp"
#include "app/run/run_plan.hpp"
#include "io/preset.hpp"
#include "mesh/discretize.hpp"
#include "mesh/surface.hpp"
#include "sim/fem_model.hpp"
#include "sim/growth_field.hpp"
#include "sim/property_field.hpp"
#include "sim/reference_shape.hpp"

#include <memory>

namespace crackle::app {

struct Scene {
    mesh::Surface surface;
    sim::GrowthField growth;
    sim::ShrinkageOptions shrinkage;
    sim::PropertyField thickness;
    sim::PropertyField young_modulus;
    sim::PropertyField threshold_stress;
    sim::PropertyField toughness;
    double poisson_ratio;
    mesh::DiscretizeOptions discretize;
    bool density_follows_thickness = false;
    std::uint64_t seed = 1;
};

/// Builds every typed input from the plan (the property fields from its layer, the element count).
std::unique_ptr<Scene> make_scene(const RunPlan& plan);

/// Discretizes the scene's surface (§5.2), density following thickness when asked.
mesh::SurfaceMesh discretize_scene(const Scene& scene, StepTimes* times);

/// The scene's layer fields for the FEM model (pointers into `scene`).
sim::LayerFields layer_fields(const Scene& scene);

} // namespace crackle::app
