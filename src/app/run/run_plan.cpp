#include "app/run/run_plan.hpp"

#include "core/error.hpp"

namespace crackle::app {

RunPlan make_run_plan(const io::Preset& preset, bool preview) {
    const fracture::MethodInfo* method = fracture::find_method(preset.text("simulation.method"));
    // The schema refuses a name no method has, naming the line; a preset built by hand may not.
    if (!method)
        throw InputError("simulation.method", "\"" + preset.text("simulation.method") + "\" is not a method",
                         "use one of the methods `crackle presets doc` lists");
    return RunPlan{io::element_count(preset, preview), io::map_size(preset), method};
}

} // namespace crackle::app
