// fem-split as a fracture method: its [simulation] keys, its options, its run and report.
#include "fracture/method.hpp"

#include "core/error.hpp"
#include "core/math.hpp"
#include "fracture/fem_split/fem_split.hpp"
#include "fracture/toolkit/fem_method.hpp"

#include <sstream>

namespace crackle::fracture {

SplitOptions split_options(const Settings& s) {
    SplitOptions o;
    o.min_angle_deg = s.number("simulation.min_angle");
    o.exclusion_radius = s.number("simulation.exclusion_radius");
    o.griffith = s.flag("simulation.griffith");
    o.smoothing_radius = s.number("simulation.smoothing_radius");
    o.vm_threshold = s.number("simulation.vm_threshold");
    o.tip_submodel_levels = static_cast<int>(s.integer("simulation.tip_submodel"));
    o.check_invariants = s.flag("simulation.check_invariants");
    if (s.is_auto("material.initiation_length"))
        o.initiation_fraction = 1.0;
    else
        o.initiation_length = s.number("material.initiation_length");
    return o;
}

namespace {

class FemSplit : public Method {
public:
    explicit FemSplit(SplitOptions options) : m_options(options) {}

    MethodResult run(const MethodInputs& in, StepTimes& times) const override {
        return run_on_wedge_layer(in, times, [&](sim::FemModel& model, Rng& rng, MethodResult& r) {
            check_initiation_length(model);
            SplitStats c;
            r.pattern = run_fem_split(model, in.options, m_options, rng, &r.run, &c);
            Json& d = r.details;
            d["removals"] = 0;
            d["subdivisions"] = c.subdivisions;
            d["splits"] = c.splits;
            d["tip_extensions"] = c.extensions;
            d["tip_arrests"] = c.arrests;
            d["edge_collapses"] = c.collapses;
            d["snapped_cuts"] = c.snaps;
            d["smoothing_moves"] = c.smoothed;
            d["von_mises_refinements"] = c.vm_refinements;
            d["tip_submodels"] = c.submodels;
            d["edge_flips"] = c.flips;
            r.summary = "elements     " + std::to_string(r.elements_initial) + " initial, "
                        + std::to_string(model.num_alive()) + " at the end; " + std::to_string(c.splits)
                        + " new cracks, " + std::to_string(c.extensions) + " tip extensions, "
                        + std::to_string(c.arrests) + " arrests (Griffith); " + std::to_string(c.collapses)
                        + " edge collapses, " + std::to_string(c.snaps) + " snapped cuts, " + std::to_string(c.flips)
                        + " flips, " + std::to_string(c.smoothed) + " smoothing moves";
        });
    }

private:
    /// The averaging disc's elements grow with its radius squared (work and memory per node):
    /// refuse a radius past about 2000 elements at this resolution, naming the largest that fits.
    void check_initiation_length(const sim::FemModel& model) const {
        constexpr double MAX_NEIGHBOURS = 2000;
        const double face_area =
            model.mesh().total_area() / static_cast<double>(std::max<std::size_t>(model.mesh().num_faces(), 1));
        double radius = m_options.initiation_length;
        if (m_options.initiation_fraction > 0)
            for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
                radius = std::max(radius, m_options.initiation_fraction * model.vertex_thickness(mesh::vertex_id(v)));
        const double neighbours = std::min(PI * sqr(radius) / face_area, static_cast<double>(model.mesh().num_faces()));
        if (neighbours <= MAX_NEIGHBOURS) return;
        std::ostringstream what, fix;
        what << "an initiation length of " << radius << " m averages each node's stress over about "
             << static_cast<long>(neighbours) << " elements (work and memory grow with that number)";
        fix << "use at most " << std::sqrt(MAX_NEIGHBOURS * face_area / PI)
            << " m at this resolution (about the layer's thickness is the physical range), or fewer elements";
        throw InputError("material.initiation_length", what.str(), fix.str());
    }

    SplitOptions m_options;
};

std::vector<KeySpec> split_keys() {
    using keys::boolean;
    using keys::integer;
    using keys::number;
    std::vector<KeySpec> s;
    s.push_back(number("simulation", "min_angle", 12.0, "deg", 1.0, 30.0,
                       "fem-split only: smallest triangle angle a cut may leave (§5.7.5); a cut that would leave "
                       "a thinner sliver goes through the nearer vertex, moved onto the crack when it is free. "
                       "Higher = better-shaped elements, cracks a little less straight."));
    s.push_back(number("simulation", "exclusion_radius", -1.0, "m", -1.0, 100.0,
                       "fem-split only: no new crack starts within this distance of an arrested crack tip, where "
                       "the stress is singular (Ch. 6). -1 = the mean layer thickness."));
    s.push_back(
        integer("simulation", "tip_submodel", 0, "", 0, 6,
                "fem-split only: take each crack tip's direction from a temporary sub-model around it, refined "
                "this many times (each halving the element size) and discarded afterwards (§5.7.8). Straighter, "
                "less mesh-dependent cracks on coarse meshes; slower. 0 = off."));
    s.push_back(number("simulation", "vm_threshold", 0.0, "", 0.0, 10.0,
                       "fem-split only, with min_element_size: once per time step, subdivide the elements around "
                       "nodes where they disagree on the von Mises stress by more than this share of the largest "
                       "principal stress (§5.7.7, Alg. 13; the thesis suggests 0.1-0.2). 0 = off."));
    s.push_back(
        number("simulation", "smoothing_radius", 0.0, "m", -1.0, 100.0,
               "fem-split only: nodes within this distance of a new crack tip are moved towards better-shaped "
               "elements (angle-based smoothing, §5.7.9). -1 = 1.5 × the mean starting edge length; 0 = off (the "
               "default: it costs time and the worst angles come from the cuts themselves)."));
    s.push_back(boolean("simulation", "griffith", true,
                        "fem-split only: a crack tip extends only while the energy it releases pays for the new "
                        "crack wall (Griffith, Alg. 11, with material.toughness); a stopped tip stays stopped. "
                        "false = tips run while the stress is over threshold, and a tip below it waits and runs "
                        "on when the load has raised its stress to the threshold."));
    s.push_back(boolean("simulation", "check_invariants", false,
                        "fem-split only, for debugging: check the mesh invariants after every topology change "
                        "(O(mesh) per event: slow); a violation stops the run with exit code 1."));
    return s;
}

} // namespace

MethodInfo fem_split_method() {
    MethodInfo info;
    info.name = "fem-split";
    info.description = "fem-split (element splitting with Griffith crack tips, the default)";
    info.keys = split_keys();
    info.make = [](const Settings& s) { return std::make_unique<FemSplit>(split_options(s)); };
    info.bytes_per_element = wedge_layer_bytes_per_element;
    // A quick look leaves out the tip sub-model (§5.7.8): straighter tips on coarse meshes, slower.
    info.preview_overrides = {"simulation.tip_submodel=0"};
    info.study = {{"fem-split", {"simulation.tip_submodel=0"}, 1.0, 0},
                  {"fem-split-tip", {"simulation.tip_submodel=2"}, 3.0, 0}};
    return info;
}

} // namespace crackle::fracture
