#pragma once
/// @file The pipeline from a preset to a crack pattern, pieces and maps, shared by the
/// simulate, bake and export commands.

#include "app/scene.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/fem_remove.hpp"
#include "fracture/statistics.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"

#include <memory>

namespace crackle::app {

struct SimulationResult {
    std::unique_ptr<Scene> scene;
    fracture::CrackPattern pattern;
    fracture::PatternStatistics statistics;
    fracture::RunStats run;
    std::size_t elements_initial = 0, elements_final = 0, nodes = 0;
    std::vector<int> crack_depth_layers; ///< mass-spring: broken layers under each open crack edge
    std::size_t newton_iterations = 0, anchor_slides = 0, factorizations = 0;
};

/// Discretizes, builds the FEM layer and runs the preset's fracture method; appends wall
/// times ("sampling", "triangulation", "assembly", "fracture", ...) to `times`.
SimulationResult run_simulation(const io::Preset& preset, StepTimes& times);

post::PostOptions post_options(const io::Preset& preset);
render::BakeOptions bake_options(const io::Preset& preset);

/// The base name of output files: bake.name, or the preset name with '/' → '-' and no
/// folder or .toml.
std::string output_name(const io::Preset& preset);

} // namespace crackle::app
