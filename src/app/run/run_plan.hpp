#pragma once
/// @file A run's plan: the preset resolved once into what every stage of the run reads (issue
/// 29): the element count, the maps' size, the method, and each stage's typed options. The
/// command that loads the preset makes it; the scene, the method's run, the pieces, the bake,
/// the pattern cache's key, the progress plan, the budget and the report take it instead of
/// reading the preset's text again.

#include "fracture/method.hpp"
#include "fracture/run.hpp"
#include "io/preset.hpp"
#include "io/resolution.hpp"
#include "mesh/surface.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"
#include "sim/fem_options.hpp"
#include "sim/growth_field.hpp"
#include "sim/property_field.hpp"
#include "sim/reference_shape.hpp"

namespace crackle::app {

/// The layer a run grows: its properties over the surface and how the surface is meshed.
struct LayerPlan {
    double thickness_min = 0, thickness_max = 0; ///< material.thickness (m), the range a variation spans
    double young_modulus = 0, threshold_stress = 0, toughness = 0, poisson_ratio = 0;
    sim::ShrinkageOptions shrinkage;
    /// [variation.thickness], [variation.young_modulus], [variation.threshold_stress],
    /// [variation.toughness], their images loaded.
    sim::VariationOptions thickness, young, threshold, toughness_variation;
    bool density_follows_thickness = false; ///< simulation.density = "thickness"
    double jitter = 0;                      ///< simulation.jitter
    int repulsion_iterations = 0;           ///< simulation.repulsion_iterations
};

struct RunPlan {
    /// simulation.elements resolved: the count the simulation starts from and, for "auto", the
    /// rule that chose it (io::element_count).
    io::ElementCount elements;
    /// The baked maps' width × height (io::map_size: bake.size, bake.size_v and the surface).
    io::MapSize map;
    /// What bake.size and bake.size_v ask for: `map` on the preset's surface, or on the tile of a
    /// pattern loaded from a file.
    io::MapSizeRequest map_request;
    /// simulation.method's registry entry: its factory, memory figure, preview reduction.
    const fracture::MethodInfo* method = nullptr;
    // Each stage's typed options (run/options.cpp maps the keys).
    mesh::SurfaceOptions surface;
    sim::GrowthOptions growth;
    fracture::FractureOptions fracture; ///< the loop keys every method reads
    sim::FemOptions fem;
    post::PostOptions post;
    /// The [bake] keys; the width × height follow the pieces' tile when baked (map_request).
    render::BakeOptions bake;
    /// The layer ([material], [variation.*], images loaded) and how its surface is meshed.
    LayerPlan layer;
    std::uint64_t seed = 1; ///< simulation.seed: every random draw of the run comes from it
};

/// The plan of a run of this preset; `preview` = the quick look's reduced model (io::element_count's
/// preview rule).
RunPlan make_run_plan(const io::Preset& preset, bool preview = false);

} // namespace crackle::app
