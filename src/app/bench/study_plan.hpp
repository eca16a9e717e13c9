#pragma once
/// @file What the speed-vs-accuracy study runs: its scenes (presets with overrides), its method
/// variants (overrides too) and the resolutions and seeds of each pair.

#include "fracture/method.hpp"

#include <optional>
#include <string>
#include <vector>

namespace crackle::app {

/// One run of the study: `crackle simulate <preset> --set <overrides>…`, or the in-process 1D
/// bar when scene == "bar".
struct StudyRun {
    std::string scene, method;
    long long elements = 0; ///< requested simulation.elements (sub-segments for the bar)
    long long seed = 1;
    std::string preset;
    std::vector<std::string> overrides; ///< scene, method, resolution and seed, in that order
};

/// A method variant of the study and the method that runs it (fracture::MethodInfo::study).
struct StudyMethod {
    std::string method; ///< simulation.method
    fracture::StudyVariant variant;
};
/// Every registered method's study variants, in the registry's order.
std::vector<StudyMethod> study_methods_of_registry();
/// The variant of that name, if a method has it.
std::optional<StudyMethod> find_study_method(const std::string& name);

/// The overrides that turn the scene's base preset into the scene ("film", "arrest", …).
std::vector<std::string> scene_overrides(const std::string& scene);
/// The base preset of a scene ("mud", "bark").
std::string scene_preset(const std::string& scene);
/// The overrides of a method variant ("fem-split-tip" → method fem-split, tip_submodel 2; "reference" →
/// fem-split with the preset's own settings).
std::vector<std::string> method_overrides(const std::string& method);

/// The scene's reference runs: fem-split with the base preset's own settings at the finest
/// affordable resolution (32000 elements; arrest 16000), seeds 101, 102, … (`seeds` of them: the
/// first four are the ones the earlier four-seed references used).
std::vector<StudyRun> reference_runs(const std::string& scene, int seeds);

/// The study's runs for these scenes and methods, `seeds` per point; quick = small resolutions.
std::vector<StudyRun> study_plan(const std::vector<std::string>& scenes, const std::vector<std::string>& methods,
                                 int seeds, bool quick);

/// The scenes that have a stored reference (patterns and the arrest height).
bool scene_has_reference(const std::string& scene);

} // namespace crackle::app
