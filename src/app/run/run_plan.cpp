#include "app/run/run_plan.hpp"

namespace crackle::app {

RunPlan make_run_plan(const io::Preset& preset, bool preview) {
    return RunPlan{io::element_count(preset, preview), io::map_size(preset)};
}

} // namespace crackle::app
