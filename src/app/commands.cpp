#include "app/commands.hpp"

#include "app/scene.hpp"
#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "fracture/preview.hpp"
#include "fracture/statistics.hpp"
#include "io/obj.hpp"
#include "io/png.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/wedge_mesh.hpp"

#include <cstdio>
#include <iomanip>

namespace crackle::app {

int presets_list(std::ostream& out) {
    for (const std::string& name : io::builtin_preset_names())
        out << std::left << std::setw(24) << name << io::builtin_preset_summary(name) << "\n";
    return 0;
}

int presets_show(const io::PresetRequest& request, std::ostream& out) {
    out << io::load_preset(request).to_toml();
    return 0;
}

int presets_doc(std::ostream& out) {
    out << io::schema_markdown();
    return 0;
}

namespace {
std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}
} // namespace

int mesh_command(const MeshArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    Timer step;
    // Everything the preset says is checked here, before any work starts.
    const io::Preset preset = io::load_preset(args.preset);
    const std::unique_ptr<Scene> scene = make_scene(preset);
    times.emplace_back("preset", step.seconds());

    const mesh::SurfaceMesh surface_mesh = discretize_scene(*scene, &times);

    step.reset();
    const mesh::MeshQuality q = mesh::mesh_quality(surface_mesh);
    times.emplace_back("quality", step.seconds());

    step.reset();
    const sim::WedgeMesh wedges = sim::extrude_wedges(surface_mesh, scene->surface, scene->thickness);
    times.emplace_back("extrusion", step.seconds());
    const auto [tmin, tmax] = std::minmax_element(wedges.vertex_thickness.begin(), wedges.vertex_thickness.end());

    // === Outputs, all or nothing
    AtomicOutput output;
    if (!args.obj_path.empty()) {
        step.reset();
        output.write(args.obj_path, io::surface_mesh_obj(surface_mesh, scene->surface));
        times.emplace_back("obj", step.seconds());
    }
    times.emplace_back("total", total.seconds());

    Json report = Json::object();
    report["command"] = "mesh";
    report["preset"] = preset.name;
    report["surface"] = mesh::to_string(scene->surface.kind());
    report["seed"] = static_cast<long long>(scene->seed);
    report["nodes"] = surface_mesh.num_vertices();
    report["faces"] = surface_mesh.num_faces();
    report["edges"] = surface_mesh.num_edges();
    report["wedge_nodes"] = wedges.nodes.size();
    report["min_angle_deg"] = q.min_angle_deg;
    report["mean_min_angle_deg"] = q.mean_min_angle_deg;
    report["fraction_min_angle_below_10deg"] = q.fraction_below_10deg;
    Json edge = Json::object();
    edge["min"] = q.edge_min;
    edge["mean"] = q.edge_mean;
    edge["max"] = q.edge_max;
    edge["std"] = q.edge_std;
    report["edge_length_m"] = edge;
    Json thick = Json::object();
    thick["min"] = *tmin;
    thick["max"] = *tmax;
    report["thickness_m"] = thick;
    Json wall = Json::object();
    for (const auto& [name, seconds] : times)
        wall[name] = seconds;
    report["wall_seconds"] = wall;
    report["peak_memory_mb"] = peak_memory_mb();
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();

    if (!global.quiet) {
        out << "crackle mesh: " << preset.name << " (" << mesh::to_string(scene->surface.kind()) << "), seed "
            << scene->seed << "\n";
        out << "  nodes        " << surface_mesh.num_vertices() << " surface vertices, " << wedges.nodes.size()
            << " wedge nodes\n";
        out << "  faces        " << surface_mesh.num_faces() << " triangles (" << surface_mesh.num_edges()
            << " edges)\n";
        out << "  min angle    " << fmt("%.2f", q.min_angle_deg) << " deg worst, " << fmt("%.2f", q.mean_min_angle_deg)
            << " deg mean of each triangle's smallest\n";
        out << "  below 10 deg " << fmt("%.3f", 100.0 * q.fraction_below_10deg) << " % of triangles\n";
        out << "  edge length  min " << fmt("%.4g", q.edge_min) << ", mean " << fmt("%.4g", q.edge_mean) << ", max "
            << fmt("%.4g", q.edge_max) << ", std " << fmt("%.3g", q.edge_std) << " m\n";
        out << "  thickness    " << fmt("%.4g", *tmin) << " .. " << fmt("%.4g", *tmax) << " m\n";
        out << "  wall time   ";
        for (const auto& [name, seconds] : times)
            out << " " << name << " " << fmt("%.3f", seconds) << " s;";
        out << "\n  peak memory  " << fmt("%.1f", peak_memory_mb()) << " MiB\n";
    }
    return 0;
}

} // namespace crackle::app

namespace crackle::app {

namespace {

std::string events_csv(const fracture::CrackPattern& p) {
    std::string csv = "time,x,y,z,u,v,kind,ratio\n";
    char buf[256];
    for (const fracture::Event& e : p.events) {
        const Vec2 uv = p.surface.periodic() ? p.surface.uv_of_domain(Vec2(e.position.x(), e.position.y()))
                                             : p.surface.uv(e.position);
        // On the cylinder the position is 3D; take uv from the surface.
        const Vec2 uvc = p.surface.kind() == mesh::SurfaceKind::Cylinder ? p.surface.uv(e.position) : uv;
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g,%.9g,%.6f,%.6f,%s,%.6f\n", e.time, e.position.x(),
                      e.position.y(), e.position.z(), uvc.x(), uvc.y(), e.kind.c_str(), e.ratio);
        csv += buf;
    }
    return csv;
}

} // namespace

int simulate_command(const SimulateArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    Timer step;
    const io::Preset preset = io::load_preset(args.preset);
    require_available_method(preset);
    const std::unique_ptr<Scene> scene = make_scene(preset);
    times.emplace_back("preset", step.seconds());

    mesh::SurfaceMesh surface_mesh = discretize_scene(*scene, &times);
    const std::size_t elements_initial = surface_mesh.num_faces();

    {
        // Element removal takes out whole elements: on elements much wider than the layer is
        // thick, most of the layer goes (thesis Fig. 5.11, failure mode F6).
        const double edge = mesh::mesh_quality(surface_mesh).edge_mean;
        const double h = 0.5 * (scene->thickness.min_value() + scene->thickness.max_value());
        if (edge > 1.5 * h && preset.number("simulation.min_element_size") == 0.0)
            log::warn("elements (", edge * 100, " cm) are much wider than the layer is thick (", h * 100,
                      " cm): element removal will take out most of the layer; raise simulation.elements or set "
                      "simulation.min_element_size");
    }
    step.reset();
    sim::FemModel model(std::move(surface_mesh), scene->surface, scene->growth, scene->shrinkage, layer_fields(*scene),
                        fem_options(preset));
    times.emplace_back("assembly", step.seconds());

    step.reset();
    Rng rng(scene->seed, RngStream::Fracture);
    fracture::RunStats run;
    const fracture::CrackPattern pattern = fracture::run_fem_remove(model, fracture_options(preset), rng, &run);
    times.emplace_back("fracture", step.seconds());
    times.emplace_back("fracture.solve", run.solve_seconds);
    times.emplace_back("fracture.stress", run.stress_seconds);
    times.emplace_back("fracture.topology", run.topology_seconds);

    step.reset();
    const fracture::PatternStatistics st = fracture::pattern_statistics(pattern);
    times.emplace_back("statistics", step.seconds());

    AtomicOutput output;
    if (!args.events_path.empty()) output.write(args.events_path, events_csv(pattern));
    if (!args.png_path.empty()) {
        const fracture::RgbImage img = fracture::preview_image(pattern, args.png_size);
        output.write(args.png_path, io::encode_png_rgb8(img.width, img.height, 3, img.pixels));
    }
    times.emplace_back("total", total.seconds());

    Json report = Json::object();
    report["command"] = "simulate";
    report["preset"] = preset.name;
    report["surface"] = mesh::to_string(scene->surface.kind());
    report["method"] = pattern.method;
    report["seed"] = static_cast<long long>(scene->seed);
    report["elements_initial"] = elements_initial;
    report["elements_final"] = model.num_alive();
    report["nodes"] = 2 * model.mesh().num_vertices();
    report["fracture_events"] = pattern.events.size();
    report["fragments"] = st.fragments;
    report["mean_fragment_area"] = st.mean_fragment_area;
    report["crack_length_per_area"] = st.crack_length_per_area;
    report["anisotropy"] = st.anisotropy;
    report["dominant_angle_deg"] = st.dominant_angle_deg;
    report["psi6"] = st.psi6;
    report["t_junction_fraction"] = st.t_junction_fraction;
    report["y_junction_fraction"] = st.y_junction_fraction;
    report["min_angle_deg"] = st.min_angle_deg;
    Json wall = Json::object();
    for (const auto& [name, seconds] : times)
        wall[name] = seconds;
    report["wall_seconds"] = wall;
    report["peak_memory_mb"] = peak_memory_mb();
    // Beyond the fixed fields: details for researchers.
    report["final_time"] = pattern.final_time;
    report["events_capped"] = pattern.events_capped;
    report["removals"] = run.removals;
    report["subdivisions"] = run.subdivisions;
    report["time_steps"] = run.time_steps;
    report["solves"] = run.solves;
    report["solver_iterations"] = run.solver_iterations;
    report["local_solves"] = run.local_solves;
    report["local_mean_nodes"] = run.local_solves ? double(run.local_nodes) / double(run.local_solves) : 0.0;
    report["local_fallbacks"] = run.local_fallbacks;
    report["global_cleanups"] = run.global_cleanups;
    report["crack_length"] = st.crack_length;
    report["junctions"] = st.junctions;
    report["axial_fraction"] = st.axial_fraction;
    report["total_area"] = st.total_area;
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();

    if (!global.quiet) {
        out << "crackle simulate: " << preset.name << " (" << mesh::to_string(scene->surface.kind()) << ", "
            << pattern.method << "), seed " << scene->seed << "\n";
        out << "  elements     " << elements_initial << " initial, " << model.num_alive() << " intact at the end ("
            << run.removals << " removed, " << run.subdivisions << " subdivisions)\n";
        out << "  time         " << fmt("%.4g", pattern.final_time) << " of "
            << fmt("%.4g", preset.number("simulation.duration"))
            << (pattern.events_capped ? " (stopped at simulation.max_events)" : "") << "; " << run.time_steps
            << " time steps, " << run.solves << " solves\n";
        out << "  fragments    " << st.fragments << ", mean area " << fmt("%.4g", st.mean_fragment_area * 1e4)
            << " cm2\n";
        out << "  cracks       " << fmt("%.4g", st.crack_length_per_area) << " m/m2, anisotropy "
            << fmt("%.3f", st.anisotropy) << " at " << fmt("%.1f", st.dominant_angle_deg) << " deg, psi6 "
            << fmt("%.3f", st.psi6) << "\n";
        out << "  junctions    " << st.junctions << " (T " << fmt("%.2f", st.t_junction_fraction) << ", Y "
            << fmt("%.2f", st.y_junction_fraction) << ")\n";
        out << "  wall time   ";
        for (const auto& [name, seconds] : times)
            out << " " << name << " " << fmt("%.3f", seconds) << " s;";
        out << "\n  peak memory  " << fmt("%.1f", peak_memory_mb()) << " MiB\n";
    }
    return 0;
}

} // namespace crackle::app
