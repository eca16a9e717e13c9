#include "app/run/run_plan.hpp"

#include "app/run/naming.hpp"
#include "app/run/options.hpp"
#include "app/run/pattern_store.hpp"
#include "app/run/run_budget.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "mesh/model_surface.hpp"

namespace crackle::app {

namespace {

const fracture::MethodInfo& find_method(const io::Preset& preset) {
    const fracture::MethodInfo* method = fracture::find_method(preset.text("simulation.method"));
    // The schema refuses a name no method has, naming the line; a preset built by hand may not.
    if (!method)
        throw InputError("simulation.method", "\"" + preset.text("simulation.method") + "\" is not a method",
                         "use one of the methods `crackle presets doc` lists");
    return *method;
}

LayerPlan layer_plan(const io::Preset& preset) {
    LayerPlan l;
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
    return l;
}

OutputPlan output_plan(const io::Preset& preset) {
    OutputPlan o;
    o.preset_file = preset_file_name(preset.name);
    o.name = preset.text("bake.name");
    o.name_where = preset.entry("bake.name").source.text();
    o.maps =
        io::parse_map_requests(preset.text("bake.maps"), preset.text("bake.bit_depth"),
                               preset.entry("bake.maps").source.text(), preset.entry("bake.bit_depth").source.text());
    o.exr = preset.flag("bake.exr");
    return o;
}

Json value_json(const Value& value) {
    if (const auto* d = std::get_if<double>(&value)) return *d;
    if (const auto* i = std::get_if<std::int64_t>(&value)) return static_cast<long long>(*i);
    if (const auto* b = std::get_if<bool>(&value)) return *b;
    if (const auto* v = std::get_if<std::vector<double>>(&value)) {
        Json a = Json::array();
        for (double x : *v)
            a.push_back(x);
        return a;
    }
    return std::get<std::string>(value);
}

/// Every key's value, key → value (simulation.elements = "auto" as the plan's count).
Json resolved_settings(const io::Preset& preset, const RunPlan& plan) {
    Json settings = Json::object();
    for (const auto& [key, entry] : preset.values())
        settings[key] = key == "simulation.elements" && preset.is_auto(key)
                            ? Json(static_cast<long long>(plan.elements.elements))
                            : value_json(entry.value);
    return settings;
}

PlanRecord plan_record(const io::Preset& preset, const RunPlan& plan) {
    PlanRecord r;
    r.preset = preset.name;
    r.settings = resolved_settings(preset, plan);
    r.toml = preset.to_toml();
    for (const auto& [key, entry] : preset.values())
        r.sources[key] = entry.source.file.empty() ? std::string() : entry.source.text();
    return r;
}

/// The quick look's reduced model (`bake --preview`): the preview's element count and what the
/// method leaves out for a preview.
io::Preset preview_preset(const io::Preset& full, const io::ElementCount& reduced) {
    std::vector<std::string> overrides = {"simulation.elements=" + std::to_string(reduced.elements)};
    for (const std::string& o : find_method(full).preview_overrides)
        overrides.push_back(o);
    if (reduced.automatic) log::info(reduced.reason);
    return io::with_overrides(full, overrides);
}

RunPlan plan_of(const io::Preset& preset, const mesh::SurfaceOptions& surface, const io::ElementCount& elements,
                const PlanRequest& request) {
    RunPlan plan;
    plan.method = &find_method(preset);
    plan.runner = plan.method->make(preset);
    if (!plan.method->bytes_per_element)
        throw std::logic_error("method " + plan.method->name
                               + " gives no memory figure (MethodInfo::bytes_per_element)");
    plan.bytes_per_element = plan.method->bytes_per_element(preset);
    plan.elements = elements;
    plan.map = io::map_size(preset);
    plan.map_request = io::map_request(preset);
    plan.surface = surface;
    plan.growth = growth_options(preset);
    plan.fracture = fracture_options(preset);
    plan.fem = fem_options(preset);
    plan.post = post_options(preset);
    plan.bake = bake_options(preset);
    plan.layer = layer_plan(preset);
    plan.seed = static_cast<std::uint64_t>(preset.integer("simulation.seed"));
    plan.bakes = request.bake;
    plan.estimate = estimate_run(plan);
    plan.simulation_key = simulation_key(preset, plan);
    plan.output = output_plan(preset);
    plan.record = plan_record(preset, plan);
    return plan;
}

} // namespace

std::string PlanRecord::where(const std::string& key) const {
    const auto it = sources.find(key);
    return it == sources.end() || it->second.empty() ? key + " (" + preset + ")" : it->second + ": " + key;
}

RunPlan make_run_plan(const io::Preset& preset, const PlanRequest& request) {
    // The surface first: a model's area sets an "auto" element count (its settings do not know it).
    const mesh::SurfaceOptions surface = surface_options(preset);
    if (surface.model && !request.discretize_only)
        throw InputError(preset.entry("surface.kind").source.text() + ": surface.kind",
                         "crackle can remesh a model (`crackle mesh`) but cannot yet simulate, bake or export on one",
                         "use surface.kind = \"plane\", \"cylinder\" or \"sphere\" for those");
    const io::ElementCount elements =
        io::element_count(preset, request.preview, surface.model ? surface.model->area() : 0.0);
    if (!request.preview) return plan_of(preset, surface, elements, request);
    // The reduced preset states its count: planned as an explicit one (no rule, no reason).
    return plan_of(preview_preset(preset, elements), surface, io::ElementCount{elements.elements, false, {}}, request);
}

} // namespace crackle::app
