#include "app/run_plan.hpp"

namespace crackle::app {

RunPlan make_run_plan(const io::Preset& preset) {
    return RunPlan{io::element_count(preset), io::map_size(preset)};
}

} // namespace crackle::app
