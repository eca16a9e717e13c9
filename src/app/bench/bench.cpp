#include "app/bench/bench.hpp"

#include "app/bench/fill_floor.hpp"
#include "app/run/pipeline.hpp"
#include "app/run/scene.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "core/strings.hpp"
#include "core/timer.hpp"
#include "fracture/statistics.hpp"
#include "io/texture_set.hpp"
#include "mesh/surface_mesh.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"

#include <cstdio>
#include <fstream>

namespace crackle::app {

Json bench_local(const std::vector<std::size_t>& sizes, int events, std::ostream& out); // bench_local.cpp

namespace {

/// Resident set size now (MiB), from /proc/self/statm.
double rss_mb() {
    std::ifstream statm("/proc/self/statm");
    double pages = 0, resident = 0;
    statm >> pages >> resident;
    return resident * 4096.0 / (1024.0 * 1024.0);
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

io::Preset mud_preset(std::size_t elements) {
    io::PresetRequest r;
    r.name_or_path = "mud";
    r.overrides = {"simulation.elements=" + std::to_string(elements)};
    return io::load_preset(r);
}

/// Equilibrium of the mud layer at the end of its shrinkage, cold start: CG vs CHOLMOD.
Json bench_solve(const std::vector<std::size_t>& sizes, std::ostream& out) {
    out << "\n### Equilibrium solve (mud layer at t = 1, cold start)\n\n"
        << "| elements | unknowns | CG time | CG iterations | model + CG memory | direct time | model + CHOLMOD memory "
           "| max difference |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (std::size_t n : sizes) {
        const io::Preset preset = mud_preset(n);
        const auto scene = make_scene(make_run_plan(preset));
        const mesh::SurfaceMesh surface_mesh = discretize_scene(*scene, nullptr);
        Json row = Json::object();
        row["elements"] = surface_mesh.num_faces();
        std::vector<Vec3> cg_x, direct_x;
        double cg_time = 0, direct_time = 0, cg_mem = 0, direct_mem = 0, disp = 0;
        int cg_its = 0;
        for (sim::SolverKind kind : {sim::SolverKind::Cg, sim::SolverKind::Direct}) {
            sim::FemOptions o = fem_options(preset);
            o.solver = kind;
            const double before = rss_mb();
            sim::FemModel model(surface_mesh, scene->surface, scene->growth, scene->shrinkage, layer_fields(*scene), o);
            model.set_time(1.0);
            Timer t;
            const sim::SolveStats s = model.relax();
            const double seconds = t.seconds();
            const double mem = rss_mb() - before;
            std::vector<Vec3>& x = kind == sim::SolverKind::Cg ? cg_x : direct_x;
            for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v) {
                x.push_back(model.top_position(mesh::vertex_id(v)));
                disp = std::max(disp, (x.back() - model.bottom_position(mesh::vertex_id(v))).norm());
            }
            if (kind == sim::SolverKind::Cg) {
                cg_time = seconds;
                cg_its = s.iterations;
                cg_mem = mem;
            } else {
                direct_time = seconds;
                direct_mem = mem;
            }
        }
        double diff = 0;
        for (std::size_t v = 0; v < cg_x.size(); ++v)
            diff = std::max(diff, (cg_x[v] - direct_x[v]).norm());
        row["unknowns"] = 3 * cg_x.size();
        row["cg_seconds"] = cg_time;
        row["cg_iterations"] = cg_its;
        row["cg_memory_mb"] = cg_mem;
        row["direct_seconds"] = direct_time;
        row["direct_memory_mb"] = direct_mem;
        row["max_difference_relative"] = disp > 0 ? diff / disp : 0.0;
        out << "| " << surface_mesh.num_faces() << " | " << 3 * cg_x.size() << " | " << fmt("%.3f s", cg_time) << " | "
            << cg_its << " | " << fmt("%.0f MiB", cg_mem) << " | " << fmt("%.3f s", direct_time) << " | "
            << fmt("%.0f MiB", direct_mem) << " | " << fmt("%.1e", disp > 0 ? diff / disp : 0.0) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

/// The mud preset run to completion with fem-remove.
Json bench_fem_remove(const std::vector<std::size_t>& sizes, std::ostream& out) {
    out << "\n### fem-remove: mud run to completion\n\n"
        << "| elements | events | wall | events/s | solve | stress | topology | fragments | local nodes/event |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (std::size_t n : sizes) {
        io::PresetRequest request;
        request.name_or_path = "mud";
        request.overrides = {"simulation.elements=" + std::to_string(n), "simulation.method=fem-remove"};
        StepTimes ignored;
        const io::Preset preset = io::load_preset(request);
        const SimulationResult r = run_simulation(make_run_plan(preset), ignored);
        const std::size_t elements = r.elements_initial;
        const fracture::RunStats& run = r.run;
        const fracture::CrackPattern& pattern = r.pattern;
        const auto& st = r.statistics;
        const double book = run.topology_seconds;
        const double events = static_cast<double>(pattern.events.size());
        Json row = Json::object();
        row["elements"] = elements;
        row["events"] = pattern.events.size();
        row["seconds"] = run.total_seconds;
        row["events_per_second"] = events / run.total_seconds;
        row["solve_seconds"] = run.solve_seconds;
        row["stress_seconds"] = run.stress_seconds;
        row["topology_seconds"] = book;
        row["fragments"] = st.fragments;
        row["local_nodes_per_event"] = run.local_solves ? double(run.local_nodes) / double(run.local_solves) : 0.0;
        auto share = [&](double s) { return fmt("%.0f %%", 100.0 * s / run.total_seconds); };
        out << "| " << elements << " | " << pattern.events.size() << " | " << fmt("%.1f s", run.total_seconds) << " | "
            << fmt("%.0f", events / run.total_seconds) << " | " << share(run.solve_seconds) << " | "
            << share(run.stress_seconds) << " | " << share(book) << " | " << st.fragments << " | "
            << fmt("%.0f", run.local_solves ? double(run.local_nodes) / double(run.local_solves) : 0.0) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

/// The mud preset cracked by mass-spring at several mass counts, next to fem-remove on the
/// same scene and mesh resolution (one mass per two triangles). From 64k masses on, the
/// mass-spring run stops after `max_breaks` (the report says so): breaks per second only.
Json bench_mass_spring(const std::vector<std::size_t>& masses, std::size_t max_breaks, std::ostream& out) {
    out << "\n### mass-spring vs fem-remove: mud (0.5 m tile, 1 cm layer)\n\n"
        << "| masses | breaks | reached t | wall | breaks/s | Newton its/break | crack m/m² | fem-remove elements | "
           "events | wall | events/s | crack m/m² |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (std::size_t n : masses) {
        auto run = [&](const std::string& method, std::size_t cap) {
            io::PresetRequest r;
            r.name_or_path = "mud";
            r.overrides = {"simulation.elements=" + std::to_string(2 * n), "simulation.method=" + method,
                           "simulation.max_events=" + std::to_string(cap)};
            StepTimes ignored;
            const io::Preset preset = io::load_preset(r);
            return run_simulation(make_run_plan(preset), ignored);
        };
        const SimulationResult ms = run("mass-spring", n >= 64000 ? max_breaks : 100000000);
        const SimulationResult fr = run("fem-remove", 100000000);
        const double ms_breaks = static_cast<double>(ms.pattern.events.size());
        const double fr_events = static_cast<double>(fr.pattern.events.size());
        Json row = Json::object();
        row["masses"] = n;
        row["breaks"] = ms.pattern.events.size();
        row["capped"] = ms.pattern.events_capped;
        row["final_time"] = ms.pattern.final_time;
        row["seconds"] = ms.run.total_seconds;
        row["breaks_per_second"] = ms_breaks / ms.run.total_seconds;
        const double newton = ms.details.find("newton_iterations")->as_number();
        row["newton_iterations"] = newton;
        row["factorizations"] = ms.details.find("factorizations")->as_number();
        row["crack_length_per_area"] = ms.statistics.crack_length_per_area;
        row["fem_remove_elements"] = fr.elements_initial;
        row["fem_remove_events"] = fr.pattern.events.size();
        row["fem_remove_seconds"] = fr.run.total_seconds;
        row["fem_remove_crack_length_per_area"] = fr.statistics.crack_length_per_area;
        out << "| " << n << " | " << ms.pattern.events.size() << (ms.pattern.events_capped ? " (cap)" : "") << " | "
            << fmt("%.2f", ms.pattern.final_time) << " | " << fmt("%.1f s", ms.run.total_seconds) << " | "
            << fmt("%.0f", ms_breaks / ms.run.total_seconds) << " | " << fmt("%.1f", newton / std::max(ms_breaks, 1.0))
            << " | " << fmt("%.1f", ms.statistics.crack_length_per_area) << " | " << fr.elements_initial << " | "
            << fr.pattern.events.size() << " | " << fmt("%.1f s", fr.run.total_seconds) << " | "
            << fmt("%.0f", fr_events / fr.run.total_seconds) << " | "
            << fmt("%.1f", fr.statistics.crack_length_per_area) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

/// A preset run through the whole simulation stage with overrides.
SimulationResult simulate_with(const std::string& name, const std::vector<std::string>& overrides) {
    io::PresetRequest r;
    r.name_or_path = name;
    r.overrides = overrides;
    StepTimes ignored;
    const io::Preset preset = io::load_preset(r);
    return run_simulation(make_run_plan(preset), ignored);
}

/// fem-split (§5.7-5.8): local vs global relaxation per event on the same capped run; the
/// default mud and bark runs by phase; uniform fine mesh vs refinement from coarse (§5.7.6).
Json bench_fem_split(bool quick, std::ostream& out) {
    Json report = Json::object();
    const std::vector<std::size_t> sizes =
        quick ? std::vector<std::size_t>{2000} : std::vector<std::size_t>{5000, 20000, 50000};
    const std::size_t cap = quick ? 100 : 300;
    out << "\n### fem-split: local vs global relaxation per event (mud, first " << cap << " events)\n\n"
        << "| elements | first solve | local: wall after it | events/s | nodes/event | global: wall after it | "
           "events/s | "
           "speed-up | fragments local / global |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (std::size_t n : sizes) {
        // Without the tip sub-model (§5.7.8), whose own local solves are the same either way.
        const std::vector<std::string> base = {"simulation.elements=" + std::to_string(n),
                                               "simulation.max_events=" + std::to_string(cap),
                                               "simulation.tip_submodel=0"};
        auto with = [&](const std::string& extra) {
            std::vector<std::string> o = base;
            o.push_back(extra);
            return simulate_with("mud", o);
        };
        const SimulationResult l = with("simulation.relaxation=local");
        const SimulationResult g = with("simulation.relaxation=global");
        const double el = double(l.pattern.events.size()), eg = double(g.pattern.events.size());
        // Per event: the first global solve both runs share is left out.
        const double sec_l = l.run.total_seconds - l.run.setup_seconds,
                     sec_g = g.run.total_seconds - g.run.setup_seconds;
        const double rate_l = el / sec_l, rate_g = eg / sec_g;
        const double nodes = l.run.local_solves ? double(l.run.local_nodes) / double(l.run.local_solves) : 0.0;
        Json row = Json::object();
        row["elements"] = l.elements_initial;
        row["setup_seconds"] = l.run.setup_seconds;
        row["local_seconds"] = sec_l;
        row["local_events"] = l.pattern.events.size();
        row["global_seconds"] = sec_g;
        row["global_events"] = g.pattern.events.size();
        row["local_nodes_per_event"] = nodes;
        row["speedup"] = rate_l / rate_g;
        out << "| " << l.elements_initial << " | " << fmt("%.2f s", l.run.setup_seconds) << " | "
            << fmt("%.2f s", sec_l) << " | " << fmt("%.0f", rate_l) << " | " << fmt("%.0f", nodes) << " | "
            << fmt("%.1f s", sec_g) << " | " << fmt("%.1f", rate_g) << " | " << fmt("%.1f×", rate_l / rate_g) << " | "
            << l.statistics.fragments << " / " << g.statistics.fragments << " |\n";
        out.flush();
        rows.push_back(row);
    }
    report["local_vs_global"] = rows;

    out << "\n### fem-split: default presets run to completion, by phase\n\n"
        << "| preset | elements (start → end) | new cracks | tip extensions | arrests | wall | solve | stress | "
           "topology | fragments | crack m/m² |\n"
        << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json full = Json::array();
    for (const char* name : {"mud", "bark"}) {
        const SimulationResult r = simulate_with(name, quick ? std::vector<std::string>{"simulation.elements=2000"}
                                                             : std::vector<std::string>{});
        auto share = [&](double s) { return fmt("%.0f %%", 100.0 * s / r.run.total_seconds); };
        Json row = Json::object();
        row["preset"] = name;
        row["elements_initial"] = r.elements_initial;
        row["elements_final"] = r.elements_final;
        const auto count = [&](const char* key) { return static_cast<long long>(r.details.find(key)->as_number()); };
        row["splits"] = count("splits");
        row["tip_extensions"] = count("tip_extensions");
        row["arrests"] = count("tip_arrests");
        row["seconds"] = r.run.total_seconds;
        row["solve_seconds"] = r.run.solve_seconds;
        row["stress_seconds"] = r.run.stress_seconds;
        row["topology_seconds"] = r.run.topology_seconds;
        row["fragments"] = r.statistics.fragments;
        out << "| " << name << " | " << r.elements_initial << " → " << r.elements_final << " | " << count("splits")
            << " | " << count("tip_extensions") << " | " << count("tip_arrests") << " | "
            << fmt("%.1f s", r.run.total_seconds) << " | " << share(r.run.solve_seconds) << " | "
            << share(r.run.stress_seconds) << " | " << share(r.run.topology_seconds) << " | " << r.statistics.fragments
            << " | " << fmt("%.1f", r.statistics.crack_length_per_area) << " |\n";
        out.flush();
        full.push_back(row);
    }
    report["presets"] = full;

    // Uniform fine vs coarse + refinement around tips, same smallest element size.
    out << "\n### fem-split: uniform fine mesh vs refinement around tips from coarse (§5.7.6)\n\n"
        << "| preset | mesh | elements (start → end) | wall | fragments | crack m/m² | anisotropy |\n"
        << "|---|---|---:|---:|---:|---:|---:|\n";
    Json adaptive = Json::array();
    for (const char* name : {"bark", "mud"}) {
        const std::size_t fine = quick ? 2000 : 8000, coarse = fine / 8;
        const SimulationResult u = simulate_with(name, {"simulation.elements=" + std::to_string(fine)});
        // Refine down to the fine mesh's longest edges (about 1.3 × its mean edge).
        const double size = 1.3 * mesh::mesh_quality(discretize_scene(*u.scene, nullptr)).edge_mean;
        const SimulationResult a = simulate_with(name, {"simulation.elements=" + std::to_string(coarse),
                                                        "simulation.min_element_size=" + fmt("%.5f", size)});
        for (const SimulationResult* r : {&u, &a}) {
            const bool is_u = r == &u;
            Json row = Json::object();
            row["preset"] = name;
            row["mesh"] = is_u ? "uniform" : "adaptive";
            row["elements_initial"] = r->elements_initial;
            row["elements_final"] = r->elements_final;
            row["seconds"] = r->run.total_seconds;
            row["fragments"] = r->statistics.fragments;
            row["crack_length_per_area"] = r->statistics.crack_length_per_area;
            out << "| " << name << " | " << (is_u ? "uniform" : fmt("coarse, refined to %.4f m", size)) << " | "
                << r->elements_initial << " → " << r->elements_final << " | " << fmt("%.1f s", r->run.total_seconds)
                << " | " << r->statistics.fragments << " | " << fmt("%.1f", r->statistics.crack_length_per_area)
                << " | " << fmt("%.2f", r->statistics.anisotropy) << " |\n";
            out.flush();
            adaptive.push_back(row);
        }
    }
    report["uniform_vs_adaptive"] = adaptive;
    return report;
}

/// The mud preset's pieces baked at several sizes: render, readback, occlusion and encoding.
Json bench_bake(const std::vector<int>& sizes, std::ostream& out) {
    io::PresetRequest r;
    r.name_or_path = "mud";
    const io::Preset preset = io::load_preset(r);
    StepTimes ignored;
    const SimulationResult sim = run_simulation(make_run_plan(preset), ignored);
    const post::PieceMesh pieces = post::build_pieces(sim.pattern, post_options(preset));
    render::GlContext context;
    out << "\n### Bake: the mud preset's pieces, all maps (" << context.description() << ")\n\n"
        << "| size | render | readback | ambient occlusion | bake total | PNG encoding (8 maps) | total | files | "
           "floor: fill + readback, no MSAA | floor + encoding | total / floor |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (int size : sizes) {
        render::BakeOptions o = bake_options(preset, pieces);
        o.width = o.height = size;
        Timer t;
        const render::TextureSet set = render::bake(pieces, o, context);
        const double bake_seconds = t.seconds();
        double encode = 0;
        const auto maps = io::encode_texture_set(set, false, &encode);
        std::size_t bytes = 0;
        for (const auto& m : maps)
            bytes += m.bytes.size();
        Json row = Json::object();
        row["size"] = size;
        row["render_seconds"] = set.render_seconds;
        row["readback_seconds"] = set.readback_seconds;
        row["ao_seconds"] = set.ao_seconds;
        row["bake_seconds"] = bake_seconds;
        row["encode_seconds"] = encode;
        row["total_seconds"] = bake_seconds + encode;
        row["megabytes"] = double(bytes) / 1e6;
        // The floor (issue 15): llvmpipe filling and reading back the same targets without MSAA
        // or geometry, plus the PNG encoding of the same bytes at the same compression.
        const double fill = render::fill_readback_floor(size, size, o.tile, context);
        const double floor = fill + encode;
        row["floor_fill_readback_seconds"] = fill;
        row["floor_seconds"] = floor;
        row["total_over_floor"] = (bake_seconds + encode) / floor;
        out << "| " << size << "² | " << fmt("%.2f s", set.render_seconds) << " | "
            << fmt("%.2f s", set.readback_seconds) << " | " << fmt("%.2f s", set.ao_seconds) << " | "
            << fmt("%.2f s", bake_seconds) << " | " << fmt("%.2f s", encode) << " | "
            << fmt("%.2f s", bake_seconds + encode) << " | " << fmt("%.1f MB", double(bytes) / 1e6) << " | "
            << fmt("%.2f s", fill) << " | " << fmt("%.2f s", floor) << " | "
            << fmt("%.2f×", (bake_seconds + encode) / floor) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

} // namespace

const std::vector<std::string>& bench_scenes() {
    static const std::vector<std::string> scenes = {"solve", "local", "fem-remove", "fem-split", "mass-spring", "bake"};
    return scenes;
}

int bench_command(const BenchArgs& args, std::ostream& out) {
    std::vector<std::string> scenes = args.scenes.empty() ? bench_scenes() : args.scenes;
    for (const auto& s : scenes)
        if (std::find(bench_scenes().begin(), bench_scenes().end(), s) == bench_scenes().end())
            throw InputError("bench", "unknown scene '" + s + "'" + did_you_mean(s, bench_scenes()),
                             "scenes are: " + join(bench_scenes(), ", "));
    Json report = Json::object();
    report["quick"] = args.quick;
    out << "# crackle bench" << (args.quick ? " (quick)" : "") << "\n";
    for (const auto& s : scenes) {
        if (s == "solve")
            report["solve"] = bench_solve(args.quick ? std::vector<std::size_t>{2000, 10000}
                                                     : std::vector<std::size_t>{10000, 50000, 200000},
                                          out);
        if (s == "local")
            report["local"] =
                bench_local(args.quick ? std::vector<std::size_t>{4000} : std::vector<std::size_t>{12500, 50000},
                            args.quick ? 3 : 15, out);
        if (s == "fem-remove")
            report["fem_remove"] = bench_fem_remove(
                args.quick ? std::vector<std::size_t>{2000} : std::vector<std::size_t>{5000, 20000}, out);
        if (s == "fem-split") report["fem_split"] = bench_fem_split(args.quick, out);
        if (s == "mass-spring")
            report["mass_spring"] = bench_mass_spring(args.quick ? std::vector<std::size_t>{1000}
                                                                 : std::vector<std::size_t>{1000, 4000, 16000, 64000},
                                                      2000, out);
        if (s == "bake")
            report["bake"] =
                bench_bake(args.quick ? std::vector<int>{256, 1024} : std::vector<int>{1024, 2048, 4096}, out);
    }
    report["peak_memory_mb"] = peak_memory_mb();
    if (!args.out_dir.empty()) write_file_atomically(std::filesystem::path(args.out_dir) / "bench.json", report.dump());
    return 0;
}

} // namespace crackle::app
