// graph-fem as a fracture method: its [simulation] keys, its options, its run and report.
#include "fracture/method.hpp"

#include "core/error.hpp"
#include "fracture/graph_fem/graph_fem.hpp"
#include "fracture/toolkit/fem_method.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace crackle::fracture {

GraphFemOptions graph_fem_options(const Settings& s) {
    GraphFemOptions o;
    o.damage_radius = s.number("simulation.damage_radius");
    o.griffith = s.flag("simulation.edge_griffith");
    return o;
}

namespace {

class GraphFem : public Method {
public:
    explicit GraphFem(GraphFemOptions options) : m_options(options) {}

    MethodResult run(const MethodInputs& in, StepTimes& times) const override {
        return run_on_wedge_layer(in, times, [&](sim::FemModel& model, Rng& rng, MethodResult& r) {
            check_damage_radius(model);
            GraphFemStats g;
            r.pattern = run_graph_fem(model, in.options, m_options, rng, &r.run, &g);
            Json& d = r.details;
            d["removals"] = 0;
            d["subdivisions"] = 0;
            d["breaks"] = g.breaks;
            d["griffith_rejections"] = g.griffith_rejections;
            d["tip_extensions"] = g.extensions;
            d["tip_arrests"] = g.arrests;
            d["graph_edges"] = g.edges;
            d["nonzeros_initial"] = g.nonzeros_initial;
            d["nonzeros_final"] = g.nonzeros_final;
            r.summary = "edges        " + std::to_string(g.edges) + " graph edges, " + std::to_string(g.breaks)
                        + " broken (" + std::to_string(g.extensions) + " by Griffith tips, " + std::to_string(g.arrests)
                        + " tips arrested, " + std::to_string(g.griffith_rejections) + " trials undone); K "
                        + std::to_string(g.nonzeros_final) + " nonzeros throughout";
        });
    }

private:
    /// Each element averages over the elements within R_d: the work and memory per element grow
    /// as R_d², so a radius of a tile's size (a typo, or metres meant as millimetres) would take
    /// hours and gigabytes (a break re-averages every neighbourhood that holds it: work ∝ neighbours²;
    /// 800 neighbours took 40 s on an 800-element mud). Refused beyond about 300 elements per
    /// neighbourhood.
    void check_damage_radius(const sim::FemModel& model) const {
        constexpr double MAX_NEIGHBOURS = 300;
        const double face_area =
            model.mesh().total_area() / static_cast<double>(std::max<std::size_t>(model.mesh().num_faces(), 1));
        const double neighbours =
            std::min(PI * sqr(m_options.damage_radius) / face_area, static_cast<double>(model.mesh().num_faces()));
        if (neighbours <= MAX_NEIGHBOURS) return;
        const double limit = std::sqrt(MAX_NEIGHBOURS * face_area / PI);
        std::ostringstream what, fix;
        what << m_options.damage_radius << " m averages each element's stress over "
             << "about " << static_cast<long>(neighbours) << " elements (work and memory grow with that number)";
        fix << "use at most " << limit << " m at this resolution; one to two element rings ("
            << std::sqrt(face_area) * 2 << " m) is the useful range, see docs/benchmarks.md";
        throw InputError("simulation.damage_radius", what.str(), fix.str());
    }

    GraphFemOptions m_options;
};

std::vector<KeySpec> graph_fem_keys() {
    using keys::boolean;
    using keys::number;
    std::vector<KeySpec> s;
    s.push_back(number("simulation", "damage_radius", 0.0, "m", 0.0, 100.0,
                       "graph-fem only: R_d, the radius over which the breaking criterion averages the element "
                       "stress (area-weighted, along the surface, not across cracks; digest §1.5). In metres, so "
                       "refining the mesh keeps the physics. On mud, one to two element rings give fewer, larger "
                       "plates; the effect is not monotone (docs/benchmarks.md). 0 = each element's own stress. "
                       "Refused when it would average over more than about 300 elements."));
    s.push_back(boolean("simulation", "edge_griffith", true,
                        "graph-fem only: cracks start where the stress reaches the threshold, then their tips run "
                        "on edge by edge while the energy a break releases pays for the new crack wall (Griffith, "
                        "with material.toughness, as fem-split's tips); a break next to a crack must pay too. "
                        "false = the paper's pure stress criterion: on mud and bark it crazes the layer with short "
                        "branched cracks that rarely close into plates."));
    return s;
}

} // namespace

MethodInfo graph_fem_method() {
    MethodInfo info;
    info.name = "graph-fem";
    info.description = "graph-fem (remeshing-free: mesh edges break, elements lose the strain along them)";
    info.keys = graph_fem_keys();
    info.make = [](const Settings& s) { return std::make_unique<GraphFem>(graph_fem_options(s)); };
    info.bytes_per_element = wedge_layer_bytes_per_element;
    info.study = {{"graph-fem", {}, 1.0, 0}};
    return info;
}

} // namespace crackle::fracture
