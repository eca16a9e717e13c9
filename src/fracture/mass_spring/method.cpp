// mass-spring as a fracture method: its [simulation] keys, its options, its run and report.
#include "fracture/method.hpp"

#include "fracture/mass_spring/mass_spring.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace crackle::fracture {

MassSpringOptions mass_spring_options(const Settings& s) {
    MassSpringOptions o;
    o.lattice = s.text("simulation.lattice") == "regular" ? Lattice::Regular : Lattice::Random;
    o.layers = static_cast<int>(s.integer("simulation.layers"));
    o.anchor_slide = s.number("simulation.anchor_slide");
    o.break_jitter = s.number("simulation.break_jitter");
    o.tolerance = s.number("simulation.newton_tolerance");
    o.max_newton_iterations = static_cast<int>(s.integer("simulation.newton_iterations"));
    return o;
}

namespace {

class MassSpring : public Method {
public:
    explicit MassSpring(MassSpringOptions options) : m_options(options) {}

    MethodResult run(const MethodInputs& in, StepTimes& times) const override {
        MethodResult r;
        Timer step;
        // One mass per Voronoi cell; a cell covers two triangles of a mesh with `elements` of
        // them, so a preset meshes the surface at the same resolution whatever its method.
        const std::size_t masses = std::max<std::size_t>(16, in.elements / 2);
        Rng sampling(in.seed, RngStream::Sampling);
        const mesh::SurfaceMesh lattice =
            mass_spring_mesh(in.surface, masses, m_options.lattice, in.sampling, sampling);
        times.emplace_back("lattice", step.seconds());
        step.reset();
        Rng rng(in.seed, RngStream::Fracture);
        MassSpringModel model(lattice, in.surface, in.growth, in.shrinkage, in.fields, m_options, rng);
        times.emplace_back("assembly", step.seconds());
        step.reset();
        MassSpringStats ms;
        r.pattern = run_mass_spring(model, in.options, rng, &r.run, &ms);
        times.emplace_back("fracture", step.seconds());
        times.emplace_back("fracture.solve", r.run.solve_seconds);
        times.emplace_back("fracture.stress", r.run.stress_seconds);
        std::size_t intact = 0;
        for (const auto& s : model.springs())
            intact += !s.broken;
        r.elements_initial = model.springs().size();
        r.elements_final = intact;
        r.nodes = model.num_vertices() * static_cast<std::size_t>(model.layers());
        Json& d = r.details;
        d["removals"] = ms.breaks;
        d["subdivisions"] = 0;
        d["newton_iterations"] = ms.newton_iterations;
        d["anchor_slides"] = ms.slides;
        d["factorizations"] = ms.factorizations;
        d["breaks"] = ms.breaks;
        // Crack-depth histogram in layers (multi-layer model, §4.3).
        Json depths = Json::object();
        std::map<long, long> hist;
        for (int layers : ms.crack_depth_layers)
            ++hist[layers];
        for (const auto& [layers, count] : hist)
            depths[std::to_string(layers)] = count;
        d["crack_depth_histogram"] = depths;
        r.summary = "springs      " + std::to_string(r.elements_initial) + " material springs on "
                    + std::to_string(r.nodes) + " masses, " + std::to_string(ms.breaks) + " broken; "
                    + std::to_string(ms.newton_iterations) + " Newton iterations, " + std::to_string(ms.factorizations)
                    + " factorizations";
        return r;
    }

private:
    MassSpringOptions m_options;
};

std::vector<KeySpec> mass_spring_keys() {
    using keys::choice;
    using keys::integer;
    using keys::number;
    std::vector<KeySpec> s;
    s.push_back(choice("simulation", "lattice", "random", {"random", "regular"},
                       "mass-spring only: random (Voronoi cells) or regular (hexagonal cells, 60° cracks)."));
    s.push_back(integer("simulation", "layers", 1, "", 1, 16,
                        "mass-spring only: stacked material layers joined by springs across the thickness; only "
                        "the bottom one is anchored (§4.3). More layers = cracks of varying depth."));
    s.push_back(number("simulation", "anchor_slide", 0.5, "", 0.0, 100.0,
                       "mass-spring only: an anchor spring longer than this (in mean spring lengths) slides along "
                       "the background (§4.1); 0 = anchors never slide."));
    s.push_back(number("simulation", "break_jitter", 0.0, "", 0.0, 0.9,
                       "mass-spring only: break strains perturbed uniformly by ± this fraction (Fig. 4.6 right): "
                       "weakens the lattice's preferred crack directions."));
    s.push_back(number("simulation", "newton_tolerance", 1e-8, "", 1e-14, 1e-3,
                       "mass-spring only: the nonlinear equilibrium (Newton) stops when the largest nodal force is "
                       "below this share of a typical spring's break force. Looser = faster, less exact."));
    s.push_back(integer("simulation", "newton_iterations", 100, "", 1, 10000,
                        "mass-spring only: Newton iterations of one relaxation before the run fails with exit code "
                        "3."));
    return s;
}

} // namespace

MethodInfo mass_spring_method() {
    MethodInfo info;
    info.name = "mass-spring";
    info.description = "mass-spring (the thesis' first model: lattice-biased, resolution-dependent)";
    info.keys = mass_spring_keys();
    info.make = [](const Settings& s) { return std::make_unique<MassSpring>(mass_spring_options(s)); };
    // 201 MB at 32000 elements with one layer and 1256 MB with four (`/usr/bin/time -f %M crackle -q
    // simulate mud --no-cache --set simulation.method=mass-spring --set simulation.elements=32000
    // --set simulation.duration=0.3`, 2026-12-03): the lattice's direct factor fills in like
    // layers^1.6.
    info.bytes_per_element = [](const Settings& s) {
        const double layers = static_cast<double>(std::max<std::int64_t>(1, s.integer("simulation.layers")));
        return 6.0e3 * std::pow(layers, 1.6);
    };
    // A global Newton solve per break: 16000 elements (8000 masses) would take about 20 min a run
    // (docs/benchmarks.md, "Mass-spring"), so the full study stops at 8000.
    info.study = {{"mass-spring-regular", {"simulation.lattice=regular"}, 3.0, 8000},
                  {"mass-spring-random", {"simulation.lattice=random"}, 3.0, 8000}};
    return info;
}

} // namespace crackle::fracture
