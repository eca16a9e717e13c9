#include "app/bench/study_plan.hpp"

#include <algorithm>

namespace crackle::app {

namespace {

/// The arrest scene's tile (m): 0.3 × 0.3, against the 0.5 × 0.5 of the presets.
constexpr double ARREST_AREA_RATIO = 0.09 / 0.25;

std::vector<long long> resolutions(const std::string& scene, const std::string& method, bool quick) {
    if (scene == "bar")
        return quick ? std::vector<long long>{16, 64} : std::vector<long long>{16, 32, 64, 128, 256, 512};
    std::vector<long long> r =
        quick ? std::vector<long long>{500, 1000} : std::vector<long long>{1000, 2000, 4000, 8000, 16000};
    // A variant may stop short of the largest count (mass-spring: a global solve per break).
    if (const std::optional<StudyMethod> m = find_study_method(method); m && m->variant.max_elements > 0)
        std::erase_if(r, [&](long long n) { return n > m->variant.max_elements; });
    if (scene == "arrest")
        for (long long& n : r)
            n = static_cast<long long>(double(n) * ARREST_AREA_RATIO * 2.0 + 0.5); // same density ×2
    return r;
}

} // namespace

std::string scene_preset(const std::string& scene) {
    return scene == "bark" || scene == "arrest" ? "bark" : "mud";
}

std::vector<std::string> scene_overrides(const std::string& scene) {
    // Uniform shrinkage of a bonded layer, no threshold noise: t* in closed form. The curved
    // films are the same layer on a cylinder (R = 0.32 m) and a sphere (R = 0.3 m): h/R ≈ 1/30.
    const std::vector<std::string> film = {"material.shrinkage=[0.003,0.003]", "variation.threshold_stress.amplitude=0",
                                           "simulation.max_events=1"};
    if (scene == "film") return film;
    if (scene == "film-cylinder" || scene == "film-sphere") {
        std::vector<std::string> o = film;
        o.push_back(scene == "film-sphere" ? "surface.kind=sphere" : "surface.kind=cylinder");
        o.push_back(scene == "film-sphere" ? "surface.size=[0.3]" : "surface.size=[2.0,0.5]");
        return o;
    }
    if (scene == "arrest") // Fig. 5.21: stretch across v, E falling from v = 1 to v = 0
        return {"surface.kind=plane",
                "surface.size=[0.3,0.3]",
                "growth.rate=[0.0008,0]",
                "variation.threshold_stress.amplitude=0",
                "variation.young_modulus.pattern=gradient",
                "variation.young_modulus.angle_deg=90",
                "variation.young_modulus.amplitude=0.8"};
    return {};
}

std::vector<StudyMethod> study_methods_of_registry() {
    std::vector<StudyMethod> all;
    for (const fracture::MethodInfo& m : fracture::methods())
        for (const fracture::StudyVariant& v : m.study)
            all.push_back({m.name, v});
    return all;
}

std::optional<StudyMethod> find_study_method(const std::string& name) {
    for (StudyMethod& m : study_methods_of_registry())
        if (m.variant.name == name) return m;
    return std::nullopt;
}

std::vector<std::string> method_overrides(const std::string& method) {
    // The reference is the default method with the preset's own settings (the converged answer).
    if (method == "reference") return {"simulation.method=fem-split"};
    const std::optional<StudyMethod> m = find_study_method(method);
    if (!m) return {"simulation.method=" + method};
    std::vector<std::string> o = {"simulation.method=" + m->method};
    o.insert(o.end(), m->variant.overrides.begin(), m->variant.overrides.end());
    return o;
}

bool scene_has_reference(const std::string& scene) {
    return scene == "mud" || scene == "bark" || scene == "arrest";
}

std::vector<StudyRun> reference_runs(const std::string& scene, int seeds) {
    std::vector<StudyRun> runs;
    const long long elements = scene == "arrest" ? 16000 : 32000;
    for (long long seed = 101; seed < 101 + seeds; ++seed) {
        StudyRun r;
        r.scene = scene;
        r.method = "reference";
        r.elements = elements;
        r.seed = seed;
        r.preset = scene_preset(scene);
        r.overrides = scene_overrides(scene);
        for (const auto& o : method_overrides("reference"))
            r.overrides.push_back(o);
        r.overrides.push_back("simulation.elements=" + std::to_string(elements));
        r.overrides.push_back("simulation.seed=" + std::to_string(seed));
        runs.push_back(r);
    }
    return runs;
}

std::vector<StudyRun> study_plan(const std::vector<std::string>& scenes, const std::vector<std::string>& methods,
                                 int seeds, bool quick) {
    std::vector<StudyRun> runs;
    for (const std::string& scene : scenes) {
        // The 1D bar is its own model (App. A): one method, one seed (it has no randomness).
        const std::vector<std::string> ms = scene == "bar" ? std::vector<std::string>{"bar1d"} : methods;
        for (const std::string& method : ms)
            for (long long n : resolutions(scene, method, quick))
                for (long long seed = 1; seed <= (scene == "bar" ? 1 : seeds); ++seed) {
                    StudyRun r;
                    r.scene = scene;
                    r.method = method;
                    r.elements = n;
                    r.seed = seed;
                    if (scene != "bar") {
                        r.preset = scene_preset(scene);
                        r.overrides = scene_overrides(scene);
                        for (const auto& o : method_overrides(method))
                            r.overrides.push_back(o);
                        r.overrides.push_back("simulation.elements=" + std::to_string(n));
                        r.overrides.push_back("simulation.seed=" + std::to_string(seed));
                    }
                    runs.push_back(r);
                }
    }
    return runs;
}

} // namespace crackle::app
