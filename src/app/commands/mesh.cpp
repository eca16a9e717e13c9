#include "app/commands/mesh.hpp"

#include "app/run/report.hpp"
#include "app/run/run_plan.hpp"
#include "app/run/scene.hpp"
#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "core/timer.hpp"
#include "io/obj.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/wedge_mesh.hpp"

#include <algorithm>

namespace crackle::app {

int mesh_command(const MeshArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    Timer step;
    // Everything the preset says is checked here, before any work starts.
    const RunPlan plan = make_run_plan(io::load_preset(args.preset), {.discretize_only = true});
    const std::unique_ptr<Scene> scene = make_scene(plan);
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
    report["preset"] = plan.record.preset;
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
        out << "crackle mesh: " << plan.record.preset << " (" << mesh::to_string(scene->surface.kind()) << "), seed "
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
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
