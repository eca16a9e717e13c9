#include "app/run/pipeline.hpp"

#include "core/timer.hpp"
#include "fracture/method.hpp"

#include <cmath>
#include <filesystem>

namespace crackle::app {

SimulationResult run_simulation(const RunPlan& plan, StepTimes& times) {
    SimulationResult r;
    r.plan = plan;
    Timer step;
    r.scene = make_scene(plan);
    times.emplace_back("preset", step.seconds());
    const Scene& scene = *r.scene;
    fracture::MethodInputs in{scene.surface,
                              scene.growth,
                              scene.shrinkage,
                              layer_fields(scene),
                              [&scene](StepTimes* t) { return discretize_scene(scene, t); },
                              scene.discretize.elements,
                              scene.discretize.sampling,
                              scene.seed,
                              plan.fracture,
                              plan.fem};
    fracture::MethodResult m = plan.runner->run(in, times);
    r.pattern = std::move(m.pattern);
    r.run = m.run;
    r.elements_initial = m.elements_initial;
    r.elements_final = m.elements_final;
    r.nodes = m.nodes;
    r.details = std::move(m.details);
    r.summary = std::move(m.summary);
    progress_stage("post");
    step.reset();
    r.statistics = fracture::pattern_statistics(r.pattern);
    times.emplace_back("statistics", step.seconds());
    return r;
}

std::vector<ProgressStage> progress_stages(const RunPlan& plan) {
    // Seconds on two cores, from `crackle bake` of bark, mud and fruit (2222, 5000 and 6980
    // elements, 2048 px): setup 0.6–0.8 s; fracture 1.8, 28 and 5.2 s (the cost per element
    // varies 8× between scenes, so this is the roughest); post 0.1–0.3 s; bake 1.6–2.2 µs and
    // encode 0.6–0.8 µs per pixel.
    const double n = static_cast<double>(plan.elements.elements);
    std::vector<ProgressStage> stages = {
        {"setup", 0.3 + 1e-4 * n}, {"fracture", 2e-5 * std::pow(n, 1.5)}, {"post", 0.05 + 3e-5 * n}};
    if (plan.bakes) {
        const double pixels = plan.map.pixels();
        stages.push_back({"bake", 2e-6 * pixels});
        stages.push_back({"encode", 0.7e-6 * pixels});
    }
    stages.push_back({"write", 0.1});
    return stages;
}

} // namespace crackle::app
