#pragma once
/// @file A run's plan: the preset resolved once into the numbers every stage of the run reads
/// (issue 29). The command that loads the preset makes it; the scene, the pattern cache's key,
/// the progress plan, the budget and the report take it instead of working the numbers out again
/// from the preset's text.

#include "fracture/method.hpp"
#include "io/preset.hpp"
#include "io/resolution.hpp"

namespace crackle::app {

struct RunPlan {
    /// simulation.elements resolved: the count the simulation starts from and, for "auto", the
    /// rule that chose it (io::element_count).
    io::ElementCount elements;
    /// The baked maps' width × height (io::map_size: bake.size, bake.size_v and the surface).
    io::MapSize map;
    /// simulation.method's registry entry: its factory, memory figure, preview reduction.
    const fracture::MethodInfo* method = nullptr;
};

/// The plan of a run of this preset; `preview` = the quick look's reduced model (io::element_count's
/// preview rule).
RunPlan make_run_plan(const io::Preset& preset, bool preview = false);

} // namespace crackle::app
