#include "app/commands/export.hpp"

#include "app/run/bake_run.hpp"
#include "app/run/report.hpp"
#include "app/run/run_budget.hpp"
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "io/mesh_files.hpp"

namespace crackle::app {

int export_command(const ExportArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    const RunPlan plan =
        make_run_plan(io::load_preset(with_bake_flags(args.preset, {.size = args.size})), {.bake = true});
    const std::string name = bake_names(plan, BakeOutputs{}).base();
    const std::filesystem::path file = args.out_path.empty() ? std::filesystem::path("out") / (name + "." + args.format)
                                                             : std::filesystem::path(args.out_path);
    check_output_path(file, "--out");
    if (!args.json_path.empty()) check_output_path(args.json_path, "--json");
    const RunBudget budget(plan, "the export of " + plan.record.preset);
    const ProgressPlan progress(progress_stages(plan));
    const Baked b = bake_pipeline(plan, times, args.shader_dir, {args.pattern_path, !args.no_cache});

    progress_stage("encode");
    Timer step;
    const std::vector<io::OutputFile> files =
        io::mesh_files(b.pieces, b.maps, {}, file, io::MeshFileOptions{args.format, args.split_pieces});
    times.emplace_back("export", step.seconds());
    progress_stage("write");
    AtomicOutput output;
    Json written = Json::array();
    for (const io::OutputFile& f : files) {
        output.write(f.path, f.bytes);
        written.push_back(f.path.string());
    }
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(b.sim, times);
    report["command"] = "export";
    report["format"] = args.format;
    report["split_pieces"] = args.split_pieces;
    report["displacement_scale_m"] = b.maps.height_scale;
    report["vertices"] = b.pieces.vertices.size();
    report["triangles"] = b.pieces.triangles.size();
    report["pieces"] = b.pieces.fragments;
    report["files"] = written;
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();
    if (!global.quiet) {
        out << "crackle export: " << plan.record.preset << " -> " << files.front().path.string() << " ("
            << b.pieces.triangles.size() << " triangles, " << b.pieces.fragments << " pieces"
            << (args.split_pieces ? " as separate nodes" : "") << ", " << b.maps.width << "×" << b.maps.height_px
            << " px maps, +Y up, metres)\n";
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
