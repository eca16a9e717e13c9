#include "app/commands/simulate.hpp"

#include "app/run/pattern_store.hpp"
#include "app/run/pipeline.hpp"
#include "app/run/report.hpp"
#include "app/run/run_budget.hpp"
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/preview.hpp"
#include "io/png.hpp"

#include <cstdio>

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
    const RunPlan plan = make_run_plan(io::load_preset(args.preset));
    for (const auto& [path, option] : {std::pair{args.save_path, "--save"},
                                       {args.events_path, "--events"},
                                       {args.png_path, "--png"},
                                       {args.json_path, "--json"}})
        if (!path.empty()) check_output_path(path, option);
    const RunBudget budget(plan, "the simulation of " + plan.record.preset);
    const ProgressPlan progress(progress_stages(plan));
    const SimulationResult r = run_simulation(plan, times);
    if (!args.no_cache) cache_store(r); // a bake of the same simulation keys reuses it

    progress_stage("write");
    AtomicOutput output;
    if (!args.save_path.empty()) output.write(args.save_path, pattern_file_bytes(r));
    if (!args.events_path.empty()) output.write(args.events_path, events_csv(r.pattern));
    if (!args.png_path.empty()) {
        const fracture::RgbImage img = fracture::preview_image(r.pattern, args.png_size);
        output.write(args.png_path, io::encode_png_rgb8(img.width, img.height, 3, img.pixels));
    }
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(r, times);
    report["command"] = "simulate";
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();

    if (!global.quiet) {
        out << "crackle simulate: " << plan.record.preset << " (" << mesh::to_string(r.scene->surface.kind()) << ", "
            << r.pattern.method << "), seed " << r.scene->seed << "\n";
        print_simulation(out, r);
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
