#include "app/pipeline.hpp"

#include "core/timer.hpp"
#include "fracture/method.hpp"

#include <filesystem>

namespace crackle::app {

SimulationResult run_simulation(const io::Preset& preset, StepTimes& times) {
    SimulationResult r;
    Timer step;
    r.scene = make_scene(preset);
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
                              fracture_options(preset),
                              fem_options(preset)};
    fracture::MethodResult m = fracture::make_method(preset)->run(in, times);
    r.pattern = std::move(m.pattern);
    r.run = m.run;
    r.elements_initial = m.elements_initial;
    r.elements_final = m.elements_final;
    r.nodes = m.nodes;
    r.details = std::move(m.details);
    r.summary = std::move(m.summary);
    step.reset();
    r.statistics = fracture::pattern_statistics(r.pattern);
    times.emplace_back("statistics", step.seconds());
    return r;
}

} // namespace crackle::app
