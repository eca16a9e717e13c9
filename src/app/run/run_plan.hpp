#pragma once
/// @file A run's plan: the preset (with the command line's flags in it) resolved once into what
/// every stage of the run reads (issue 29): the element count, the maps' size, the method with its
/// typed options, each stage's typed options, the budget estimate, the pattern cache's key, the
/// output names and maps, and the record the report and the pattern file keep. The command that
/// loads the preset makes it; the scene, the method's run, the pieces, the bake, the cache, the
/// progress plan, the budget, the batch and the report read the plan and never a preset key.

#include "fracture/method.hpp"
#include "fracture/run.hpp"
#include "io/map_set.hpp"
#include "io/preset.hpp"
#include "io/resolution.hpp"
#include "mesh/surface.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"
#include "sim/fem_options.hpp"
#include "sim/growth_field.hpp"
#include "sim/property_field.hpp"
#include "sim/reference_shape.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

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

/// Rough cost of one run on two cores (run/run_budget.cpp).
struct RunEstimate {
    double seconds = 0;     ///< the progress plan's stage weights, summed (within a few × of the truth)
    double bytes = 0;       ///< peak resident memory (within about 1.5×; docs/reliability.md)
    std::string memory_key; ///< the key that dominates the memory: "bake.size" or "simulation.elements"
};

/// What a bake writes: its names and maps ([bake] name, maps, bit_depth, exr).
struct OutputPlan {
    std::string preset_file;          ///< the preset's name as a file name ({preset} in names)
    std::string name;                 ///< bake.name ("" = the command's or "{preset}")
    std::string name_where;           ///< where bake.name was set, for messages
    std::vector<io::MapRequest> maps; ///< bake.maps at bake.bit_depth, checked
    bool exr = false;                 ///< bake.exr: the displacement also as 32-bit float EXR
};

/// The resolved preset as the report and the pattern file record it.
struct PlanRecord {
    std::string preset; ///< the preset's name as asked for ("bark/table-5-2-a", "my.toml")
    /// Every key's value, "auto" element counts as the plan's: the report's `settings`.
    Json settings = Json::object();
    std::string toml; ///< the resolved preset as TOML, each key's source noted (the pattern file's copy)
    std::map<std::string, std::string> sources; ///< key → "file:line", "--set", "--size"; "" = default

    /// "presets/x.toml:3: bake.size", or "bake.size (mud)" for a default: where to fix the key.
    std::string where(const std::string& key) const;
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
    /// simulation.method's registry entry: its name, memory figure, preview reduction, study.
    const fracture::MethodInfo* method = nullptr;
    /// The method made with its typed options (MethodInfo::make from its [simulation] keys).
    std::shared_ptr<const fracture::Method> runner;
    double bytes_per_element = 0; ///< the method's peak memory per initial element at these options
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
    bool bakes = false;     ///< the run bakes maps (the estimate counts them)
    RunEstimate estimate;   ///< time and memory, before any work (run/run_budget.hpp)
    /// Everything that decides the pattern, as text: the pattern cache's key (run/pattern_store.hpp).
    std::string simulation_key;
    OutputPlan output;
    PlanRecord record;
};

/// How a command plans its run.
struct PlanRequest {
    bool bake = false; ///< the run bakes maps (bake, export)
    /// The run only meshes the surface (`crackle mesh`): the one use a model surface has so far.
    bool discretize_only = false;
    bool preview = false; ///< the quick look's reduced model (`bake --preview`): io::element_count's
                          ///< preview count and the method's MethodInfo::preview_overrides
};

/// The plan of a run of this preset. Throws InputError for what only a plan can check (the method's
/// options, bake.maps, a variation image).
RunPlan make_run_plan(const io::Preset& preset, const PlanRequest& request = {});

} // namespace crackle::app
