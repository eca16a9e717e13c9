/// @file `crackle bench local`: one crack event's local relaxation (§5.8) against a warm global
/// re-solve of the same event, on mud layers at a fixed resolution per layer thickness (issue 15;
/// docs/perf-limits.md measured the limit on these machines).
#include "app/bench/bench.hpp"
#include "app/bench/bench_scale.hpp"
#include "app/run/scene.hpp"
#include "core/json.hpp"
#include "core/rng.hpp"
#include "core/timer.hpp"
#include "fracture/toolkit/fem_loop.hpp"
#include "io/preset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace crackle::app {

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
}

std::string f(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

} // namespace

Json bench_local(const std::vector<std::size_t>& sizes, int events, std::ostream& out) {
    out << "\n### One crack event: local relaxation against a warm global re-solve (mud, 2 elements per h²)\n\n"
        << "| elements | tile | local set (nodes) | local | warm global CG | global / local | displacement error "
           "(median, max) |\n"
        << "|---:|---:|---:|---:|---:|---:|---:|\n";
    Json rows = Json::array();
    for (std::size_t n : sizes) {
        // The tile grows with the count, so the elements per layer thickness stay those of "auto".
        const double side = mud_auto_side(static_cast<long long>(n));
        io::PresetRequest request;
        request.name_or_path = "mud";
        request.overrides = {"simulation.elements=" + std::to_string(n),
                             "surface.size=[" + f("%.6g", side) + ", " + f("%.6g", side) + "]"};
        const io::Preset preset = io::load_preset(request);
        const auto scene = make_scene(make_run_plan(preset));
        sim::FemModel model(discretize_scene(*scene, nullptr), scene->surface, scene->growth, scene->shrinkage,
                            layer_fields(*scene), fem_options(preset));
        model.set_time(1.0);
        model.relax();
        const sim::LocalRelaxOptions local_options; // what the fracture loops use
        Rng rng(7, RngStream::Test);
        std::vector<double> local_s, global_s, ratio, error, nodes;
        for (int e = 0; e < events; ++e) {
            // An event: an element well inside the tile is removed (fem-remove's event).
            mesh::FaceId f = mesh::NO_FACE;
            while (f == mesh::NO_FACE) {
                const auto c = mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(model.mesh().num_faces())));
                const auto p = model.mesh().face_positions(c);
                const Vec3 m = (p[0] + p[1] + p[2]) / 3.0;
                if (model.alive(c) && std::abs(m.x()) < 0.3 * side && std::abs(m.y()) < 0.3 * side) f = c;
            }
            std::vector<Vec3> before;
            for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
                before.push_back(model.top_position(mesh::vertex_id(v)));
            std::vector<std::size_t> seeds;
            for (mesh::VertexId w : model.mesh().faces[f].v)
                seeds.push_back(mesh::ix(w));
            std::sort(seeds.begin(), seeds.end());
            model.remove_element(f);
            sim::FemModel local = model; // the same state; its solver is set up lazily, like the loop's
            double radius = fracture::initial_radius(local, local_options.tolerance);
            Timer t;
            const sim::SolveStats ls = local.relax_local(seeds, radius, local_options);
            local_s.push_back(t.seconds());
            nodes.push_back(static_cast<double>(ls.nodes));
            model.max_residual_force(); // the tracked residual is current before the clock starts
            t.reset();
            model.relax(); // warm: from the positions before the event, on the tracked residual
            global_s.push_back(t.seconds());
            ratio.push_back(global_s.back() / local_s.back());
            double change = 0, miss = 0;
            for (std::size_t v = 0; v < before.size(); ++v) {
                const Vec3 truth = model.top_position(mesh::vertex_id(v));
                change += (truth - before[v]).squaredNorm();
                miss += (local.top_position(mesh::vertex_id(v)) - truth).squaredNorm();
            }
            error.push_back(change > 0 ? std::sqrt(miss / change) : 0.0);
        }
        Json row = Json::object();
        row["elements"] = n;
        row["tile_m"] = side;
        row["local_nodes"] = median(nodes);
        row["local_seconds"] = median(local_s);
        row["global_seconds"] = median(global_s);
        row["ratio"] = median(ratio);
        row["error_median"] = median(error);
        row["error_max"] = *std::max_element(error.begin(), error.end());
        out << "| " << n << " | " << f("%.2f m", side) << " | " << f("%.0f", median(nodes)) << " | "
            << f("%.2f ms", 1e3 * median(local_s)) << " | " << f("%.1f ms", 1e3 * median(global_s)) << " | "
            << f("%.1f×", median(ratio)) << " | " << f("%.2f %%", 100 * median(error)) << ", "
            << f("%.2f %%", 100 * row["error_max"].as_number()) << " |\n";
        out.flush();
        rows.push_back(row);
    }
    return rows;
}

} // namespace crackle::app
