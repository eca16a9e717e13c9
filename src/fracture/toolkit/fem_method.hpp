#pragma once
/// @file The frame every method on the wedge FEM shares: mesh the scene (§5.2), build the layer
/// (§5.3-5.5), run the method's loop on it, and record the wall times and sizes they all report.

#include "fracture/method.hpp"
#include "sim/fem_model.hpp"

namespace crackle::fracture {

/// Peak bytes per initial element of a run on the wedge layer, for the run budget. Measured with
/// `/usr/bin/time -f %M crackle -q simulate mud --no-cache --set simulation.elements=N --set
/// simulation.duration=0.3` (2026-12-03): 74 MB at 2000 elements, 197 MB at 32000 (cg), 223 MB with
/// the direct solver, 684 MB at 128000 direct. Cracks add elements as a run goes (fem-split), hence
/// the margin.
inline double wedge_layer_bytes_per_element(const Settings& s) {
    return s.text("simulation.solver") == "direct" ? 7.5e3 : 6.5e3;
}

/// Runs `loop(model, rng, result)` (which sets result.pattern, .run, .details, .summary) on the
/// scene's wedge layer; fills the sizes and appends "assembly", "fracture" and its phases.
template <class Loop> MethodResult run_on_wedge_layer(const MethodInputs& in, StepTimes& times, Loop&& loop) {
    MethodResult r;
    mesh::SurfaceMesh surface_mesh = in.discretize(&times);
    r.elements_initial = surface_mesh.num_faces();
    Timer step;
    sim::FemModel model(std::move(surface_mesh), in.surface, in.growth, in.shrinkage, in.fields, in.fem);
    times.emplace_back("assembly", step.seconds());
    step.reset();
    Rng rng(in.seed, RngStream::Fracture);
    loop(model, rng, r);
    times.emplace_back("fracture", step.seconds());
    times.emplace_back("fracture.solve", r.run.solve_seconds);
    times.emplace_back("fracture.stress", r.run.stress_seconds);
    times.emplace_back("fracture.topology", r.run.topology_seconds);
    r.elements_final = model.num_alive();
    r.nodes = 2 * model.mesh().num_vertices();
    return r;
}

} // namespace crackle::fracture
