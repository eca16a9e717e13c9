#pragma once
/// @file The pipeline from a preset to a crack pattern, pieces and maps, shared by the
/// simulate, bake and export commands.

#include "app/run/scene.hpp"
#include "core/json.hpp"
#include "core/progress.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "fracture/statistics.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"

#include <memory>

namespace crackle::app {

struct SimulationResult {
    RunPlan plan; ///< what the run was planned with (its element count, its maps' size)
    std::unique_ptr<Scene> scene;
    fracture::CrackPattern pattern;
    fracture::PatternStatistics statistics;
    fracture::RunStats run;
    std::size_t elements_initial = 0, elements_final = 0, nodes = 0;
    Json details = Json::object();            ///< the method's own counters (fracture::MethodResult::details)
    std::string summary;                      ///< the method's line of the summary
    std::string pattern_source = "simulated"; ///< "simulated", "cache" or "file" (app/pattern_store.hpp)
};

/// Builds the scene and runs the plan's fracture method (RunPlan::runner); appends wall times
/// ("preset", "sampling", "triangulation", "assembly", "fracture", ...) to `times`.
SimulationResult run_simulation(const RunPlan& plan, StepTimes& times);

/// The stages of a run for the progress report (ProgressPlan), weighted by rough wall times
/// from the element count and the map size: setup, fracture, post, then when the plan bakes the
/// maps (bake, encode), and write. Never changes a result.
std::vector<ProgressStage> progress_stages(const RunPlan& plan);

} // namespace crackle::app
