#include "app/commands.hpp"

#include "app/pipeline.hpp"
#include "app/scene.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "fracture/preview.hpp"
#include "fracture/statistics.hpp"
#include "io/mesh_export.hpp"
#include "io/obj.hpp"
#include "io/png.hpp"
#include "io/resolution.hpp"
#include "io/texture_set.hpp"
#include "mesh/surface_mesh.hpp"
#include "render/gl_context.hpp"
#include "sim/wedge_mesh.hpp"

#include <cstdio>
#include <iomanip>
#include <map>

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

namespace {

double mean_thickness(const fracture::CrackPattern& p) {
    double sum = 0;
    for (double h : p.thickness)
        sum += h;
    return p.thickness.empty() ? 0.0 : sum / double(p.thickness.size());
}

/// The report fields of design.md for a finished simulation, plus details.
Json simulation_report(const io::Preset& preset, const SimulationResult& r, const StepTimes& times) {
    const auto& st = r.statistics;
    Json report = Json::object();
    report["preset"] = preset.name;
    report["surface"] = mesh::to_string(r.scene->surface.kind());
    report["method"] = r.pattern.method;
    report["seed"] = static_cast<long long>(r.scene->seed);
    report["elements_initial"] = r.elements_initial;
    if (const io::ElementCount count = io::element_count(preset); count.automatic)
        report["elements_rule"] = "auto: " + count.reason;
    report["elements_final"] = r.elements_final;
    report["nodes"] = r.nodes;
    report["fracture_events"] = r.pattern.events.size();
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
    report["final_time"] = r.pattern.final_time;
    report["events_capped"] = r.pattern.events_capped;
    // The method's own counters (fracture::MethodResult::details), then the common ones.
    for (const auto& [key, value] : r.details.members())
        report[key] = value;
    report["time_steps"] = r.run.time_steps;
    report["solves"] = r.run.solves;
    report["solver_iterations"] = r.run.solver_iterations;
    report["local_solves"] = r.run.local_solves;
    report["local_mean_nodes"] = r.run.local_solves ? double(r.run.local_nodes) / double(r.run.local_solves) : 0.0;
    report["local_fallbacks"] = r.run.local_fallbacks;
    report["global_cleanups"] = r.run.global_cleanups;
    report["drift_relaxations"] = r.run.drift_relaxations;
    report["stiffness_rebuilds"] = r.run.stiffness_rebuilds;
    report["crack_length"] = st.crack_length;
    report["junctions"] = st.junctions;
    report["axial_fraction"] = st.axial_fraction;
    report["total_area"] = st.total_area;
    // Shape statistics of the speed-vs-accuracy study (docs/benchmarks.md): crack chains shorter
    // than two layer thicknesses are straight by construction and left out of the tortuosity.
    report["fragment_area_cv"] = st.fragment_area_cv;
    report["tortuosity"] = fracture::crack_path_statistics(r.pattern, 2.0 * mean_thickness(r.pattern)).tortuosity;
    double first = -1;
    for (const auto& e : r.pattern.events)
        if (first < 0 || e.time < first) first = e.time;
    report["first_event_time"] = first; // −1 when nothing broke
    return report;
}

void print_times(std::ostream& out, const StepTimes& times) {
    out << "  wall time   ";
    for (const auto& [name, seconds] : times)
        out << " " << name << " " << fmt("%.3f", seconds) << " s;";
    out << "\n  peak memory  " << fmt("%.1f", peak_memory_mb()) << " MiB\n";
}

void print_simulation(std::ostream& out, const io::Preset& preset, const SimulationResult& r) {
    const auto& st = r.statistics;
    out << "  " << r.summary << "\n";
    out << "  time         " << fmt("%.4g", r.pattern.final_time) << " of "
        << fmt("%.4g", preset.number("simulation.duration"))
        << (r.pattern.events_capped ? " (stopped at simulation.max_events)" : "") << "; " << r.run.time_steps
        << " time steps, " << r.run.solves << " solves\n";
    out << "  fragments    " << st.fragments << ", mean area " << fmt("%.4g", st.mean_fragment_area * 1e4) << " cm2\n";
    out << "  cracks       " << fmt("%.4g", st.crack_length_per_area) << " m/m2, anisotropy "
        << fmt("%.3f", st.anisotropy) << " at " << fmt("%.1f", st.dominant_angle_deg) << " deg, psi6 "
        << fmt("%.3f", st.psi6) << "\n";
    out << "  junctions    " << st.junctions << " (T " << fmt("%.2f", st.t_junction_fraction) << ", Y "
        << fmt("%.2f", st.y_junction_fraction) << ")\n";
}

/// Everything a bake or export needs: the simulation, the pieces and the maps.
struct Baked {
    SimulationResult sim;
    post::PieceMesh pieces;
    render::TextureSet maps;
};

Baked bake_pipeline(const io::Preset& preset, StepTimes& times, const std::string& shader_dir) {
    if (!shader_dir.empty())
        for (const char* name : {"common.glsl", "bake.vert", "bake.frag", "id.frag", "fullscreen.vert", "ao.frag"})
            if (!std::filesystem::is_regular_file(std::filesystem::path(shader_dir) / name))
                throw InputError("--shader-dir " + shader_dir, std::string("no ") + name + " there",
                                 "point it at a copy of the shaders/ folder");
    Baked b;
    b.sim = run_simulation(preset, times);
    Timer step;
    b.pieces = post::build_pieces(b.sim.pattern, post_options(preset));
    times.emplace_back("post", step.seconds());
    progress_stage("bake");
    step.reset();
    render::GlContext context;
    times.emplace_back("gl_context", step.seconds());
    step.reset();
    render::BakeOptions options = bake_options(preset, b.pieces);
    options.shader_dir = shader_dir;
    b.maps = render::bake(b.pieces, options, context);
    times.emplace_back("bake", step.seconds());
    times.emplace_back("bake.render", b.maps.render_seconds);
    times.emplace_back("bake.readback", b.maps.readback_seconds);
    times.emplace_back("bake.ambient_occlusion", b.maps.ao_seconds);
    return b;
}

/// Applies the bake command's shortcuts to the preset request.
io::PresetRequest with_bake_overrides(io::PresetRequest request, const std::string& size, bool preview) {
    if (preview) {
        request.overrides.insert(request.overrides.begin(), "bake.size=512");
        request.overrides.insert(request.overrides.begin(), "bake.samples=2");
    }
    if (!size.empty()) {
        const auto parsed = parse_map_size(size);
        if (!parsed)
            throw InputError("--size " + size, "not a map size",
                             "give the longer side in pixels (2048) or width x height (2048x1024), 16 to 16384 each");
        request.overrides.push_back("bake.size=" + std::to_string(parsed->first));
        request.overrides.push_back("bake.size_v=" + std::to_string(parsed->second));
    }
    return request;
}

/// The bake's preset; --preview swaps in the reduced model (io::element_count's preview rule,
/// no tip sub-model) after the preset's own values are known.
io::Preset load_bake_preset(const BakeArgs& args) {
    io::PresetRequest request = with_bake_overrides(args.preset, args.size, args.preview);
    if (!args.preview) return io::load_preset(request);
    const io::Preset full = io::load_preset(request);
    const io::ElementCount reduced = io::element_count(full, true);
    request.overrides.push_back("simulation.elements=" + std::to_string(reduced.elements));
    if (full.text("simulation.method") == "fem-split") request.overrides.push_back("simulation.tip_submodel=0");
    if (reduced.automatic) log::info(reduced.reason);
    return io::load_preset(request);
}

} // namespace

std::optional<std::pair<int, int>> parse_map_size(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    const int n = std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra);
    auto ok = [](int side) { return side >= 16 && side <= 16384; };
    if (n == 1 && ok(w)) return std::make_pair(w, 0);
    if (n == 3 && (x == 'x' || x == 'X') && ok(w) && ok(h)) return std::make_pair(w, h);
    return std::nullopt;
}

int simulate_command(const SimulateArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    const io::Preset preset = io::load_preset(args.preset);
    require_available_method(preset);
    const ProgressPlan plan(progress_stages(preset, false));
    const SimulationResult r = run_simulation(preset, times);

    progress_stage("write");
    AtomicOutput output;
    if (!args.events_path.empty()) output.write(args.events_path, events_csv(r.pattern));
    if (!args.png_path.empty()) {
        const fracture::RgbImage img = fracture::preview_image(r.pattern, args.png_size);
        output.write(args.png_path, io::encode_png_rgb8(img.width, img.height, 3, img.pixels));
    }
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(preset, r, times);
    report["command"] = "simulate";
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();

    if (!global.quiet) {
        out << "crackle simulate: " << preset.name << " (" << mesh::to_string(r.scene->surface.kind()) << ", "
            << r.pattern.method << "), seed " << r.scene->seed << "\n";
        print_simulation(out, preset, r);
        print_times(out, times);
    }
    return 0;
}

int bake_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    const io::Preset preset = load_bake_preset(args);
    require_available_method(preset);
    const std::string name = output_name(preset);
    const std::filesystem::path dir =
        args.out_dir.empty() ? std::filesystem::path("out") : std::filesystem::path(args.out_dir);
    const ProgressPlan plan(progress_stages(preset, true));
    const Baked b = bake_pipeline(preset, times, args.shader_dir);

    progress_stage("encode");
    double encode = 0;
    const std::vector<io::EncodedMap> maps = io::encode_texture_set(b.maps, preset.flag("bake.exr"), &encode);
    times.emplace_back("encode", encode);
    progress_stage("write");
    AtomicOutput output;
    Json files = Json::array();
    for (const io::EncodedMap& m : maps) {
        const std::filesystem::path path = io::map_path(dir, name, m);
        output.write(path, m.bytes);
        files.push_back(path.string());
    }
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(preset, b.sim, times);
    report["command"] = "bake";
    report["size"] = std::max(b.maps.width, b.maps.height_px);
    report["width"] = b.maps.width;
    report["height"] = b.maps.height_px;
    report["displacement_scale_m"] = b.maps.height_scale;
    report["files"] = files;
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();

    if (!global.quiet) {
        out << "crackle bake: " << preset.name << " (" << mesh::to_string(b.sim.scene->surface.kind()) << ", "
            << b.sim.pattern.method << "), seed " << b.sim.scene->seed << ", " << b.maps.width << "×"
            << b.maps.height_px << " px\n";
        print_simulation(out, preset, b.sim);
        out << "  maps         " << maps.size() << " files in " << dir.string() << "/ (" << name
            << "_Color.png ...); displacement 1.0 = " << fmt("%.4g", b.maps.height_scale * 1000) << " mm\n";
        print_times(out, times);
    }
    return 0;
}

int export_command(const ExportArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    const io::Preset preset = io::load_preset(with_bake_overrides(args.preset, args.size, false));
    require_available_method(preset);
    const std::string name = output_name(preset);
    const std::filesystem::path file = args.out_path.empty() ? std::filesystem::path("out") / (name + "." + args.format)
                                                             : std::filesystem::path(args.out_path);
    const std::filesystem::path dir = file.parent_path();
    const std::string base = file.stem().string();
    const ProgressPlan plan(progress_stages(preset, true));
    const Baked b = bake_pipeline(preset, times, args.shader_dir);

    progress_stage("encode");
    Timer step;
    const io::ExportMesh mesh = io::export_mesh(b.pieces);
    double encode = 0;
    const std::vector<io::EncodedMap> encoded = io::encode_texture_set(b.maps, false, &encode);
    io::MaterialMaps mat;
    mat.name = base;
    for (const io::EncodedMap& m : encoded) {
        if (m.suffix == "Color") mat.color = m;
        if (m.suffix == "NormalGL") mat.normal = m;
    }
    mat.orm = io::encode_orm(b.maps);
    auto uri = [&](const io::EncodedMap& m) { return io::map_path("", base, m).string(); };
    mat.color_uri = uri(mat.color);
    mat.normal_uri = uri(mat.normal);
    mat.orm_uri = uri(mat.orm);
    mat.roughness_uri = base + "_Roughness.png";
    mat.ao_uri = base + "_AmbientOcclusion.png";

    progress_stage("write");
    AtomicOutput output;
    std::vector<std::string> written;
    auto write = [&](const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
        output.write(path, bytes);
        written.push_back(path.string());
    };
    if (args.format == "glb") {
        write(file, io::gltf_bytes(mesh, mat, true));
    } else {
        // External maps next to the mesh file.
        for (const io::EncodedMap& m : encoded)
            write(io::map_path(dir, base, m), m.bytes);
        write(io::map_path(dir, base, mat.orm), mat.orm.bytes);
        if (args.format == "gltf") {
            write(file, io::gltf_bytes(mesh, mat, false));
        } else {
            const auto [obj, mtl] = io::obj_files(mesh, mat, base + ".mtl");
            output.write(file, obj);
            output.write(dir / (base + ".mtl"), mtl);
            written.push_back(file.string());
            written.push_back((dir / (base + ".mtl")).string());
        }
    }
    times.emplace_back("export", step.seconds());
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(preset, b.sim, times);
    report["command"] = "export";
    report["format"] = args.format;
    report["vertices"] = mesh.positions.size() / 3;
    report["triangles"] = mesh.indices.size() / 3;
    Json files = Json::array();
    for (const auto& w : written)
        files.push_back(w);
    report["files"] = files;
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();
    if (!global.quiet) {
        out << "crackle export: " << preset.name << " -> " << file.string() << " (" << mesh.positions.size() / 3
            << " vertices, " << mesh.indices.size() / 3 << " triangles, " << b.maps.width << "×" << b.maps.height_px
            << " px maps)\n";
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
