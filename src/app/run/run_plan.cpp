#include "app/run/run_plan.hpp"

#include "app/run/options.hpp"
#include "core/error.hpp"

namespace crackle::app {

RunPlan make_run_plan(const io::Preset& preset, bool preview) {
    const fracture::MethodInfo* method = fracture::find_method(preset.text("simulation.method"));
    // The schema refuses a name no method has, naming the line; a preset built by hand may not.
    if (!method)
        throw InputError("simulation.method", "\"" + preset.text("simulation.method") + "\" is not a method",
                         "use one of the methods `crackle presets doc` lists");
    RunPlan plan;
    plan.elements = io::element_count(preset, preview);
    plan.map = io::map_size(preset);
    plan.map_request = io::map_request(preset);
    plan.method = method;
    plan.surface = surface_options(preset);
    plan.growth = growth_options(preset);
    plan.fracture = fracture_options(preset);
    plan.fem = fem_options(preset);
    plan.post = post_options(preset);
    plan.bake = bake_options(preset);
    plan.seed = static_cast<std::uint64_t>(preset.integer("simulation.seed"));
    LayerPlan& l = plan.layer;
    const auto& thickness = preset.numbers("material.thickness");
    const auto& shrink = preset.numbers("material.shrinkage");
    l.thickness_min = thickness[0];
    l.thickness_max = thickness[1];
    l.young_modulus = preset.number("material.young_modulus");
    l.threshold_stress = preset.number("material.threshold_stress");
    l.toughness = preset.number("material.toughness");
    l.poisson_ratio = preset.number("material.poisson_ratio");
    l.shrinkage = sim::ShrinkageOptions{shrink[0], shrink[1]};
    l.thickness = variation_options(preset, "thickness");
    l.young = variation_options(preset, "young_modulus");
    l.threshold = variation_options(preset, "threshold_stress");
    l.toughness_variation = variation_options(preset, "toughness");
    l.density_follows_thickness = preset.text("simulation.density") == "thickness";
    l.jitter = preset.number("simulation.jitter");
    l.repulsion_iterations = static_cast<int>(preset.integer("simulation.repulsion_iterations"));
    return plan;
}

} // namespace crackle::app
