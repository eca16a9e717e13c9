#pragma once
/// @file The fracture stage as one interface: what every method starts from (the grown surface,
/// its layer, the common loop options), what it returns (the crack-pattern contract, common
/// counters, its own named details), and the registry the app, the preset schema, `presets
/// doc`, the run budget, the preview, the study and the tests read. A method is one folder: its
/// loop, its [simulation] keys, the mapping from them to its typed options, its memory figure, its
/// preview reduction and its study variants (its `method_info()`, listed in method.cpp).

#include "core/json.hpp"
#include "core/settings.hpp"
#include "core/timer.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "mesh/sampling.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/fem_model.hpp"
#include "sim/growth_field.hpp"
#include "sim/reference_shape.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace crackle::fracture {

/// What a method starts from: the scene (references into the caller's, alive for the run).
struct MethodInputs {
    const mesh::Surface& surface;
    const sim::GrowthField& growth;
    const sim::ShrinkageOptions& shrinkage;
    sim::LayerFields fields;
    /// The scene's FEM mesh (§5.2: repelled points, Delaunay) at `elements`, its density as the
    /// preset asks; appends "sampling" and "triangulation" wall times.
    std::function<mesh::SurfaceMesh(StepTimes*)> discretize;
    std::size_t elements = 0;       ///< simulation.elements: the resolution every method follows
    mesh::SamplingOptions sampling; ///< for methods that place their own points (mass-spring)
    std::uint64_t seed = 1;         ///< every random draw of the run comes from it
    FractureOptions options;        ///< the loop keys every method reads
    sim::FemOptions fem;            ///< the equilibrium solver keys
};

/// What a method returns.
struct MethodResult {
    CrackPattern pattern;
    RunStats run;
    std::size_t elements_initial = 0, elements_final = 0, nodes = 0;
    /// The method's own counters, under the names of the JSON report, in report order.
    Json details = Json::object();
    /// One line for `crackle simulate`'s summary: what the method did, in its own terms.
    std::string summary;
};

class Method {
public:
    virtual ~Method() = default;
    /// Runs to `inputs.options.duration`; appends the wall times of its steps to `times`.
    virtual MethodResult run(const MethodInputs& inputs, StepTimes& times) const = 0;
};

/// One variant of a method that the speed-vs-accuracy study charts (`crackle bench study`).
struct StudyVariant {
    std::string name;                   ///< "fem-split-tip"
    std::vector<std::string> overrides; ///< preset overrides after simulation.method = the method
    double cost = 1.0;                  ///< time per element against fem-split's (the progress weight)
    long long max_elements = 0;         ///< the largest element count the full study affords; 0 = all
};

struct MethodInfo {
    std::string name;        ///< simulation.method value: "fem-split"
    std::string description; ///< a sentence for the schema's reference of simulation.method
    /// Its own [simulation] keys (group = name): the schema lists them under the method.
    std::vector<KeySpec> keys;
    /// Maps the settings to its typed options and makes the method.
    std::function<std::unique_ptr<Method>(const Settings&)> make;
    /// Peak bytes per initial element at these settings, for the run budget (measured; the method's
    /// method.cpp says how).
    std::function<double(const Settings&)> bytes_per_element;
    /// What `bake --preview` switches off for a quick look (besides the preview's element count).
    std::vector<std::string> preview_overrides;
    /// Its variants in the speed-vs-accuracy study, in chart order.
    std::vector<StudyVariant> study;
};

/// Every method, in documentation order.
const std::vector<MethodInfo>& methods();
/// Bumped by every registration: what caches the registry (the preset schema) rebuilds on it.
int methods_generation();

/// Adds a method for as long as it lives (tests register a method of their own; the built-in ones
/// are listed in method.cpp). The name must be new.
class ScopedMethod {
public:
    explicit ScopedMethod(MethodInfo info);
    ~ScopedMethod();
    ScopedMethod(const ScopedMethod&) = delete;
    ScopedMethod& operator=(const ScopedMethod&) = delete;

private:
    std::string m_name;
};
/// The method of that name, or nullptr.
const MethodInfo* find_method(const std::string& name);
std::vector<std::string> method_names();
/// The method the settings name (simulation.method), its options mapped from them. Throws
/// InputError for a name no method has (the preset schema refuses those first, naming the line).
std::unique_ptr<Method> make_method(const Settings& settings);

} // namespace crackle::fracture
