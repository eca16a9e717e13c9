#include "app/bench.hpp"

#include "app/pipeline.hpp"
#include "app/scene.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "core/strings.hpp"
#include "core/timer.hpp"
#include "fracture/statistics.hpp"
#include "io/texture_set.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"

#include <cstdio>
#include <fstream>

namespace crackle::app {

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
        const auto scene = make_scene(preset);
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
        const io::Preset preset = mud_preset(n);
        const auto scene = make_scene(preset);
        mesh::SurfaceMesh surface_mesh = discretize_scene(*scene, nullptr);
        const std::size_t elements = surface_mesh.num_faces();
        sim::FemModel model(std::move(surface_mesh), scene->surface, scene->growth, scene->shrinkage,
                            layer_fields(*scene), fem_options(preset));
        Rng rng(scene->seed, RngStream::Fracture);
        fracture::RunStats run;
        const fracture::CrackPattern pattern = fracture::run_fem_remove(model, fracture_options(preset), rng, &run);
        const auto st = fracture::pattern_statistics(pattern);
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

/// The mud preset's pieces baked at several sizes: render, readback, occlusion and encoding.
Json bench_bake(const std::vector<int>& sizes, std::ostream& out) {
    io::PresetRequest r;
    r.name_or_path = "mud";
    const io::Preset preset = io::load_preset(r);
    StepTimes ignored;
    const SimulationResult sim = run_simulation(preset, ignored);
    const post::PieceMesh pieces = post::build_pieces(sim.pattern, post_options(preset));
    render::GlContext context;
    out << "\n### Bake: the mud preset's pieces, all maps (" << context.description() << ")\n\n"
        << "| size | render | readback | ambient occlusion | bake total | PNG encoding (8 maps) | total | files |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (int size : sizes) {
        render::BakeOptions o = bake_options(preset);
        o.size = size;
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
        out << "| " << size << "² | " << fmt("%.2f s", set.render_seconds) << " | "
            << fmt("%.2f s", set.readback_seconds) << " | " << fmt("%.2f s", set.ao_seconds) << " | "
            << fmt("%.2f s", bake_seconds) << " | " << fmt("%.2f s", encode) << " | "
            << fmt("%.2f s", bake_seconds + encode) << " | " << fmt("%.1f MB", double(bytes) / 1e6) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

} // namespace

const std::vector<std::string>& bench_scenes() {
    static const std::vector<std::string> scenes = {"solve", "fem-remove", "bake"};
    return scenes;
}

int bench_command(const BenchArgs& args, std::ostream& out) {
    std::vector<std::string> scenes = args.scenes.empty() ? bench_scenes() : args.scenes;
    for (const auto& s : scenes)
        if (std::find(bench_scenes().begin(), bench_scenes().end(), s) == bench_scenes().end())
            throw InputError("bench", "unknown scene '" + s + "'" + did_you_mean(s, bench_scenes()),
                             "scenes are: solve, fem-remove, bake");
    Json report = Json::object();
    report["quick"] = args.quick;
    out << "# crackle bench" << (args.quick ? " (quick)" : "") << "\n";
    for (const auto& s : scenes) {
        if (s == "solve")
            report["solve"] = bench_solve(args.quick ? std::vector<std::size_t>{2000, 10000}
                                                     : std::vector<std::size_t>{10000, 50000, 200000},
                                          out);
        if (s == "fem-remove")
            report["fem_remove"] = bench_fem_remove(
                args.quick ? std::vector<std::size_t>{2000} : std::vector<std::size_t>{5000, 20000}, out);
        if (s == "bake")
            report["bake"] =
                bench_bake(args.quick ? std::vector<int>{256, 1024} : std::vector<int>{1024, 2048, 4096}, out);
    }
    report["peak_memory_mb"] = peak_memory_mb();
    if (!args.out_dir.empty()) write_file_atomically(std::filesystem::path(args.out_dir) / "bench.json", report.dump());
    return 0;
}

} // namespace crackle::app
